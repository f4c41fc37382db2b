"""Issue 10: a long check does not hold the server up. Checks run in a worker thread; a hover sent
while one runs is answered before that check's diagnostics are published (over a real LSP
connection). Also the pieces: the map of a stale analysis onto the current text, the bounded walk
of workspace folders."""

from __future__ import annotations

import asyncio
import os
import sys
from pathlib import Path

from lsprotocol import types

from rdcd_core.source import Span
from server import workspace_files
from server.documents import Shift
from tests.server.conftest import EXAMPLES, Session, doc, position_of

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.check_speed import generate  # noqa: E402

BIG = "file:///long/big.rdcd"
SMALL = "file:///long/small.rdcd"


def test_hover_during_a_long_check_is_answered_before_its_diagnostics(lsp: Session) -> None:
    small = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    lsp.open(SMALL, small)
    big = generate(20_000)  # seconds of checking, whatever the machine

    async def scenario() -> tuple[bool, bool, object]:
        lsp.versions[BIG] = 1
        lsp.client.text_document_did_open(types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=BIG, language_id="rdcd", version=1, text=big)))
        await asyncio.sleep(0.2)  # past the debounce: the check has started
        on_small = await lsp.client.text_document_hover_async(types.HoverParams(
            text_document=doc(SMALL), position=position_of(small, "turn_direction", delta=2)))
        small_first = BIG not in lsp.client.published  # type: ignore[attr-defined]
        # the big document has no finished analysis yet: an empty answer, but at once
        await lsp.client.text_document_hover_async(types.HoverParams(
            text_document=doc(BIG), position=position_of(big, "turn_direction", delta=2)))
        big_first = BIG not in lsp.client.published  # type: ignore[attr-defined]
        return small_first, big_first, on_small

    small_first, big_first, on_small = lsp.run(scenario())
    assert on_small is not None and "turn_direction" in on_small.contents.value
    assert small_first and big_first, "hover waited for the long check"
    lsp.diagnostics(BIG, 1, timeout=120)  # the check still ends and publishes its diagnostics
    lsp.close_document(BIG)
    lsp.close_document(SMALL)


def test_hover_after_an_edit_answers_from_the_previous_analysis_away_from_the_edit(lsp: Session) -> None:
    uri = "file:///long/edited.rdcd"
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    lsp.open(uri, text)
    position = position_of(text, "turn_direction", delta=2)
    params = types.HoverParams(text_document=doc(uri), position=position)
    before = lsp.request(types.TEXT_DOCUMENT_HOVER, params)
    # an edit at the end, then a hover at once (the debounce has not even run out)
    end = position_of(text, "deployment")
    lsp.change(uri, [types.TextDocumentContentChangePartial(
        range=types.Range(start=end, end=end), text="// edited\n")], wait=False)
    after = lsp.request(types.TEXT_DOCUMENT_HOVER, params)
    assert after is not None and after.contents.value == before.contents.value
    assert after.range == before.range
    lsp.diagnostics(uri, 2)
    lsp.close_document(uri)


def test_shift_maps_offsets_outside_the_edit() -> None:
    old = "role A { self.x() == 1; }\nrole B { }\n"
    new = old.replace("== 1", "== 12345")
    shift = Shift(old, new)
    assert shift.to_old(5) == 5  # before the edit
    assert shift.to_old(new.index("role B")) == old.index("role B")  # after it
    assert shift.to_old(new.index("345")) is None  # inside it
    assert shift.to_new(Span(old.index("B"), old.index("B") + 1)) == Span(new.index("B"), new.index("B") + 1)
    assert shift.to_new(Span(old.index("1;"), old.index("1;") + 2)) is None  # across it
    same = Shift(old, old)
    assert same.to_old(len(old)) == len(old) and same.to_new(Span(0, len(old))) == Span(0, len(old))


def test_workspace_walk_is_bounded(tmp_path: Path) -> None:
    for index in range(30):
        (tmp_path / f"p{index:02}.rdcd").write_text("role A { }\n", encoding="utf-8")
    for skipped in (".git", "node_modules", "__pycache__"):
        (tmp_path / skipped).mkdir()
        (tmp_path / skipped / "hidden.rdcd").write_text("role H { }\n", encoding="utf-8")
    deep = tmp_path
    for level in range(workspace_files.MAX_DEPTH + 3):
        deep = deep / f"d{level}"
    deep.mkdir(parents=True)
    (deep / "deep.rdcd").write_text("role D { }\n", encoding="utf-8")
    os.symlink(tmp_path, tmp_path / "loop")  # a link back up: never followed
    os.mkfifo(tmp_path / "fifo.rdcd")  # reading it would block the server

    everything = list(workspace_files.program_files(tmp_path, workspace_files.Budget()))
    names = {path.name for path in everything}
    assert len(everything) == 30 and "hidden.rdcd" not in names and "deep.rdcd" not in names
    assert "fifo.rdcd" not in names

    budget = workspace_files.Budget(entries=10)
    assert len(list(workspace_files.program_files(tmp_path, budget))) < 10
    spent = workspace_files.Budget(seconds=0)
    assert len(list(workspace_files.program_files(tmp_path, spent))) < 64


def test_workspace_symbol_with_a_root_of_slash_answers() -> None:
    """The walk of / stops at its budget; the request is answered (in a thread meanwhile)."""
    session = Session(root_uri="file:///")
    try:
        result = session.request(types.WORKSPACE_SYMBOL, types.WorkspaceSymbolParams(query="zzzz"))
        assert isinstance(result, list)
    finally:
        session.close()
