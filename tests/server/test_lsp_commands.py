"""``rdcd.simulate`` (child process, progress, cancellation) and ``rdcd.showBytecode``."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import pytest
from lsprotocol import types

from tests.server.conftest import EXAMPLES, Session

OBSTACLE = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()


def simulate(lsp: Session, uri: str, options: dict) -> asyncio.Future:
    params = types.ExecuteCommandParams(command="rdcd.simulate", arguments=[uri, options])
    request = lsp.client.protocol.send_request_async(types.WORKSPACE_EXECUTE_COMMAND, params)
    return asyncio.ensure_future(request, loop=lsp.loop)


def test_simulate_returns_report_and_plot(lsp: Session) -> None:
    uri = "file:///virtual/simulate.rdcd"
    lsp.open(uri, OBSTACLE)
    before = set(lsp.client.progress_reports)
    result = lsp.run(simulate(lsp, uri, {"config": "car7", "obstacle": "none", "duration": 1, "seed": 0,
                                         "world": "lattice"}), timeout=120)
    assert isinstance(result["report"], dict) and result["report"]
    assert Path(result["plotPath"]).is_file()
    json.dumps(result)
    tokens = set(lsp.client.progress_reports) - before
    assert tokens, "the simulation reports work done progress"
    reports = lsp.client.progress_reports[tokens.pop()]
    assert isinstance(reports[0], types.WorkDoneProgressBegin)
    assert isinstance(reports[-1], types.WorkDoneProgressEnd)


def test_simulate_can_be_cancelled(lsp: Session) -> None:
    uri = "file:///virtual/simulate-cancel.rdcd"
    lsp.open(uri, OBSTACLE)
    before = set(lsp.client.progress_reports)
    running = simulate(lsp, uri, {"config": "car7", "duration": 3600, "seed": 0})

    async def cancel_when_started() -> None:
        while not set(lsp.client.progress_reports) - before:
            await asyncio.sleep(0.05)
        await asyncio.sleep(0.3)
        token = (set(lsp.client.progress_reports) - before).pop()
        lsp.client.window_work_done_progress_cancel(types.WorkDoneProgressCancelParams(token=token))

    lsp.run(cancel_when_started(), timeout=60)
    with pytest.raises(Exception):  # noqa: B017 - the request ends with a cancellation error
        lsp.run(running, timeout=30)


def test_simulate_bad_arguments(lsp: Session) -> None:
    with pytest.raises(Exception):  # noqa: B017
        lsp.run(simulate(lsp, "file:///virtual/not-open-and-missing.rdcd", {}), timeout=30)
