"""The server's copy of a document is the editor's, through the real server over stdio.

Random documents in every line-break style, with form feeds, U+2028 and the other characters
``str.splitlines`` breaks at in their comments, get random incremental edits holding every
line-break-like character, in each position encoding. The server's text is observed only
through what it answers:

- after every didChange (of one to three changes, now and then a whole-document one), its Format
  Document edits applied to the client's text give exactly ``format_text`` of the client's text
  (a drifted copy comments out or deletes code), and its range formatting ``format_range``'s;
- at the end, its diagnostics are those of ``check_text`` of the client's text, on the lines
  and columns the LSP's definition of a line gives (the lines ``rdcd check`` prints);
- and the edited document answers semantic tokens, folding ranges and document symbols exactly
  as a document freshly opened with the client's text does.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from lsprotocol import types

from rdcd_core.formatter import format_range, format_text
from rdcd_core.frontend import check_text
from rdcd_core.source import Span
from rdcd_core.syntax.tables import tables
from tests import line_reference as ref
from tests.server.conftest import ROOT, Session, doc, make_client

SEED = """role Wheel {{ // wheels turn{a}and stop
  constant speed := 3; /* a block{b}comment
  over lines{c} */
  self.center_position == EAST_WEST;
  startup go() {{
    // page{d}break
    self.turnContinuously(speed);
  }}
}}

/* end{e}of{f}roles */
deployment {{ Wheel }}
"""
WEIRD = ref.NOT_LINE_BREAKS + ["\r", "\n", "\r\n"]  # what goes into block comments
IN_LINE_COMMENTS = ref.NOT_LINE_BREAKS + ["x", " "]  # a \r or \n would end a line comment
WILD = [*ref.LINE_BREAK_LIKE, "}", "{", ";", "self.", "-1", "😀", "é", "//", "/*", "*/", "role X { }", " "]
counter = itertools.count()


class EncodedSession(Session):
    """A session (as conftest's) whose client offers one position encoding."""

    def __init__(self, encoding: str) -> None:
        self.encoding = encoding
        self.loop = asyncio.new_event_loop()
        self.client = make_client()
        self.versions: dict[str, int] = {}
        command = [sys.executable, "-m", "server", "--debounce-ms", "10", "--log-level", "ERROR"]
        self.run(self.client.start_io(*command, cwd=str(ROOT)))
        capabilities = types.ClientCapabilities(
            general=types.GeneralClientCapabilities(position_encodings=[encoding]),
            text_document=types.TextDocumentClientCapabilities(
                publish_diagnostics=types.PublishDiagnosticsClientCapabilities(version_support=True)))
        params = types.InitializeParams(capabilities=capabilities)
        self.initialize_result = self.run(self.client.initialize_session(params))


@pytest.fixture(scope="module", params=ref.ENCODINGS)
def session(request: pytest.FixtureRequest) -> Iterator[EncodedSession]:
    started = EncodedSession(request.param)
    assert started.initialize_result.capabilities.position_encoding == request.param
    yield started
    started.close()


# -- documents and edits ----------------------------------------------------------------------------
@st.composite
def documents(draw: st.DrawFn) -> str:
    fill = {key: draw(st.sampled_from(IN_LINE_COMMENTS if key in "ad" else WEIRD)) for key in "abcdef"}
    text = SEED.format(**fill)
    newline = draw(st.sampled_from(["\n", "\r\n", "\r"]))
    return text.replace("\n", newline) if newline != "\n" else text


def _comments_and_gaps(text: str) -> tuple[list[tuple[int, int, bool]], list[tuple[int, int]]]:
    """Where text can go without breaking the program: inside comments (start, end, is a block
    comment) and in the white space between tokens."""
    lexed = tables().lexer.lex(text)
    comments = [(c.span.start, c.span.end, c.text.startswith("/*")) for c in lexed.comments]
    spans = sorted([(t.start, t.end) for t in lexed.tokens] + [(a, b) for a, b, _ in comments])
    gaps = [(left[1], right[0]) for left, right in zip(spans, spans[1:], strict=False)]
    return comments, gaps


@st.composite
def edits(draw: st.DrawFn, text: str) -> tuple[int, int, str]:
    """One edit (start, end, new text) of ``text``, mostly one that keeps the program valid."""
    comments, gaps = _comments_and_gaps(text)
    # every offset but the one inside a \r\n, which no position names
    offsets = [i for i in range(len(text) + 1) if not (0 < i < len(text) and text[i - 1:i + 1] == "\r\n")]
    kind = draw(st.sampled_from(["comment", "comment", "gap", "gap", "new comment", "wild"]))
    if kind == "comment" and comments:
        start, end, block = draw(st.sampled_from(comments))
        inner_start, inner_end = start + 2, end - (2 if block else 0)
        at = draw(st.sampled_from([i for i in offsets if inner_start <= i <= max(inner_start, inner_end)]))
        chars = WEIRD if block else IN_LINE_COMMENTS
        return at, at, "".join(draw(st.lists(st.sampled_from(chars), min_size=1, max_size=4)))
    if kind in ("gap", "new comment") and gaps:
        start, end = draw(st.sampled_from(gaps))
        space = "".join(draw(st.lists(st.sampled_from(["\n", "\r\n", "\r", " ", "\f", "\t"]), min_size=1,
                                      max_size=4)))
        if kind == "new comment":
            body = "".join(draw(st.lists(st.sampled_from(IN_LINE_COMMENTS), max_size=4)))
            block = "".join(draw(st.lists(st.sampled_from(WEIRD), max_size=4)))
            space = draw(st.sampled_from([f" //{body}{space}", f"{space}/*{block}*/ "]))
        return start, end, space
    start = draw(st.sampled_from(offsets))
    end = draw(st.sampled_from([i for i in offsets if start <= i <= start + 12]))
    return start, end, "".join(draw(st.lists(st.sampled_from(WILD), max_size=3)))


# -- what the server answers -------------------------------------------------------------------------
def range_of(text: str, start: int, end: int, encoding: str) -> types.Range:
    (a, b), (c, d) = ref.position(text, start, encoding), ref.position(text, end, encoding)
    return types.Range(start=types.Position(line=a, character=b), end=types.Position(line=c, character=d))


def apply_lsp_edits(text: str, edits: list[types.TextEdit], encoding: str) -> str:
    spans = [(ref.offset(text, e.range.start.line, e.range.start.character, encoding),
              ref.offset(text, e.range.end.line, e.range.end.character, encoding), e.new_text) for e in edits]
    for start, end, new_text in sorted(spans, reverse=True):
        text = text[:start] + new_text + text[end:]
    return text


def assert_formats_like_the_client(session: EncodedSession, uri: str, text: str) -> None:
    params = types.DocumentFormattingParams(text_document=doc(uri),
                                            options=types.FormattingOptions(tab_size=2, insert_spaces=True))
    edits = session.request(types.TEXT_DOCUMENT_FORMATTING, params) or []
    expected = format_text(text)
    if expected is None:
        assert edits == [], "edits for a text with syntax errors"
    else:
        assert apply_lsp_edits(text, edits, session.encoding) == expected


def assert_range_formats_like_the_client(session: EncodedSession, uri: str, text: str, line: int) -> None:
    """Range formatting of one line (and the roles on it) answers as ``format_range`` of the client's text."""
    start = ref.offset(text, line, 0, session.encoding)
    params = types.DocumentRangeFormattingParams(
        text_document=doc(uri), range=range_of(text, start, start, session.encoding),
        options=types.FormattingOptions(tab_size=2, insert_spaces=True))
    edits = session.request(types.TEXT_DOCUMENT_RANGE_FORMATTING, params) or []
    expected = text
    wanted = format_range(text, Span(start, start)) or []
    for edit in sorted(wanted, key=lambda e: e.span.start, reverse=True):
        expected = expected[:edit.span.start] + edit.new_text + expected[edit.span.end:]
    assert apply_lsp_edits(text, list(edits), session.encoding) == expected


def assert_diagnostics_like_the_cli(session: EncodedSession, uri: str, text: str) -> None:
    published = session.diagnostics(uri, session.versions[uri])
    expected = check_text(text).diagnostics
    assert [(d.code, d.message) for d in published] == [(d.code, d.message) for d in expected]
    for got, want in zip(published, expected, strict=True):
        assert got.range == range_of(text, want.span.start, want.span.end, session.encoding)


def views(session: EncodedSession, uri: str) -> tuple[Any, ...]:
    tokens = session.request(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
                             types.SemanticTokensParams(text_document=doc(uri)))
    folds = session.request(types.TEXT_DOCUMENT_FOLDING_RANGE,
                            types.FoldingRangeParams(text_document=doc(uri)))
    symbols = session.request(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL,
                              types.DocumentSymbolParams(text_document=doc(uri)))
    return tokens.data, folds, symbols


def assert_views_like_a_fresh_copy(session: EncodedSession, uri: str, text: str) -> None:
    fresh = f"file:///virtual/sync-fresh-{next(counter)}.rdcd"
    session.client.text_document_did_open(types.DidOpenTextDocumentParams(
        text_document=types.TextDocumentItem(uri=fresh, language_id="rdcd", version=1, text=text)))
    try:
        assert views(session, uri) == views(session, fresh)
    finally:
        session.close_document(fresh)


@settings(max_examples=30, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_the_servers_text_is_the_clients(session: EncodedSession, data: st.DataObject) -> None:
    uri = f"file:///virtual/sync-{next(counter)}.rdcd"
    text = data.draw(documents(), label="document")
    session.open(uri, text)
    assert_formats_like_the_client(session, uri, text)
    for _ in range(data.draw(st.integers(1, 8), label="notifications")):
        changes: list[Any] = []
        for _ in range(data.draw(st.integers(1, 3), label="changes in one notification")):
            # each change's range is read on the text the one before it left, as the LSP says
            start, end, insert = data.draw(edits(text), label="edit")
            changes.append(types.TextDocumentContentChangePartial(
                range=range_of(text, start, end, session.encoding), text=insert))
            text = text[:start] + insert + text[end:]
        if data.draw(st.integers(0, 9), label="whole document") == 0:
            changes.append(types.TextDocumentContentChangeWholeDocument(text=text))
        session.change(uri, changes, wait=False)
        assert_formats_like_the_client(session, uri, text)
        assert_range_formats_like_the_client(session, uri, text, data.draw(st.integers(0, 30), label="line"))
    event("formattable at the end" if format_text(text) is not None else "syntax errors at the end")
    assert_diagnostics_like_the_cli(session, uri, text)
    assert_views_like_a_fresh_copy(session, uri, text)
    session.close_document(uri)


def test_an_edit_below_u2028_and_a_form_feed_lands_where_the_editor_put_it(lsp: Session) -> None:
    """The example of the issue: pygls counted the U+2028 and the form feed as line ends, so this
    edit landed in the comment two lines up, and Format Document then answered for a text the
    user does not have."""
    uri = "file:///virtual/sync-example.rdcd"
    text = ("role A { // a\u2028b\n  /* page\fbreak */\n  self.y() > 0;\n  self.y() > 1;\n}\n\n"
            "deployment { A }\n")
    lsp.open(uri, text)
    at = types.Position(line=2, character=len("  self.y() > "))
    insert = types.TextDocumentContentChangePartial(range=types.Range(start=at, end=at), text="5+")
    assert lsp.change(uri, [insert]) == []  # no syntax error: the 5+ is not inside the comment
    text = text.replace("> 0", "> 5+0")
    params = types.DocumentFormattingParams(text_document=doc(uri),
                                            options=types.FormattingOptions(tab_size=2, insert_spaces=True))
    edits = lsp.request(types.TEXT_DOCUMENT_FORMATTING, params)
    assert apply_lsp_edits(text, list(edits or []), "utf-16") == text.replace("5+0", "5 + 0")
    lsp.close_document(uri)


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_diagnostics_are_on_the_lines_rdcd_check_prints(lsp: Session, tmp_path: Path, newline: str) -> None:
    text = newline.join(["role A { // x\u2028y\x85z", "  /* page\fbreak */ self.y() > EAST_WST;",
                         "  self.y() >\v 0;", "}", "deployment { A }", ""])
    uri = f"file:///virtual/sync-cli-{len(newline)}-{newline == chr(13)}.rdcd"
    published = lsp.open(uri, text)
    path = tmp_path / "prog.rdcd"
    path.write_bytes(text.encode("utf-8"))
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", "--format", "json", str(path)],
                          cwd=ROOT, capture_output=True, timeout=60)
    printed = json.loads(done.stdout)["diagnostics"]
    assert len(published) == len(printed) > 0
    for got, want in zip(published, printed, strict=True):
        # the CLI counts code points from 1; every character before the faults is in the BMP
        assert (got.range.start.line + 1, got.range.start.character + 1) == (want["line"], want["column"])
        assert got.code == want["code"]
    lsp.close_document(uri)
