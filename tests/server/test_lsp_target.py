"""The editor setting ``rdcd.target``: open documents are checked for the chosen target, and a
change of the setting checks them again (a real server over stdio)."""

from __future__ import annotations

import asyncio
import time

from lsprotocol import types

from tests.server.conftest import EXAMPLES, Session

SNAKE = (EXAMPLES / "snake_wave.rdcd").read_text(encoding="utf-8")


def _published(session: Session, uri: str, count: int, timeout: float = 20) -> list[types.Diagnostic]:
    """The diagnostics of the ``count``-th publication for ``uri``."""
    async def wait() -> list[types.Diagnostic]:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            published = session.client.published.get(uri, [])  # type: ignore[attr-defined]
            if len(published) >= count:
                return list(published[count - 1].diagnostics)
            await asyncio.sleep(0.005)
        raise TimeoutError(f"fewer than {count} publications for {uri}")

    return session.run(wait(), timeout + 5)


def test_the_target_setting_chooses_what_programs_are_checked_for() -> None:
    session = Session(init_options={"rdcd": {"target": "original"}})
    try:
        uri = "file:///virtual/snake-original.rdcd"
        codes = [d.code for d in session.open(uri, SNAKE)]
        assert "W604" in codes  # the handler would re-fire on the firmware
        session.client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
            settings={"rdcd": {"target": "default"}}))
        assert "W604" not in [d.code for d in _published(session, uri, 2)]
        session.client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
            settings={"rdcd.target": "original"}))
        assert "W604" in [d.code for d in _published(session, uri, 3)]
        listing = session.request(types.WORKSPACE_EXECUTE_COMMAND, types.ExecuteCommandParams(
            command="rdcd.showBytecode", arguments=[uri]))
        assert "EQUALS_2" not in listing  # compiled for the firmware, which lacks it
    finally:
        session.close()


def test_the_extensions_setting_offers_exactly_the_targets() -> None:
    import json

    from rdcd_core.compiler import TARGETS
    from tests.server.conftest import ROOT

    manifest = json.loads((ROOT / "vscode-extension" / "package.json").read_text(encoding="utf-8"))
    setting = manifest["contributes"]["configuration"]["properties"]["rdcd.target"]
    assert setting["enum"] == list(TARGETS) and setting["default"] == "default"
