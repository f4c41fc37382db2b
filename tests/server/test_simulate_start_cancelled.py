"""A simulation cancelled while its child process is being started (the server ending, the user
cancelling) answers like any other cancellation: JsonRpcRequestCancelled, never a CancelledError
escaping into pygls (which asyncio then prints as a traceback)."""

from __future__ import annotations

import asyncio
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from pygls.exceptions import JsonRpcRequestCancelled

from server import commands


async def _cancelled_while_starting(*args: Any, **kwargs: Any) -> Any:
    raise asyncio.CancelledError


def test_cancelled_while_the_child_starts(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(commands.asyncio, "create_subprocess_exec", _cancelled_while_starting)
    server = SimpleNamespace(protocol=SimpleNamespace(_request_futures={}, msg_id=1),
                             client_capabilities=SimpleNamespace(window=None))
    uri = (tmp_path / "program.rdcd").as_uri()

    async def run() -> None:
        await commands._simulate(server, uri, "role A { }\n", {"config": "car7"}, tmp_path, "program.rdcd")

    with pytest.raises(JsonRpcRequestCancelled, match="cancelled"):
        asyncio.run(run())
