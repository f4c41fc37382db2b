"""The server's edit applier (``server.sync.apply_change``) against plain string splicing: for any
text holding any line-break-like character and any edit a client can express, in every position
encoding, the result is the client's text."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from lsprotocol import types

from server.sync import apply_change, apply_changes
from tests import line_reference as ref

PIECES = [*ref.LINE_BREAK_LIKE, "a", "b", " ", "é", "😀", "\t", "//", "/*", "*/", "role A { }", "\ufeff"]
TEXTS = st.lists(st.sampled_from(PIECES), max_size=25).map("".join)


def addressable(text: str, offset: int) -> bool:
    """A position can name every offset but the one between the \\r and \\n of a CRLF."""
    return not (0 < offset < len(text) and text[offset - 1] == "\r" and text[offset] == "\n")


def change(text: str, start: int, end: int, insert: str,
           encoding: str) -> types.TextDocumentContentChangePartial:
    (a, b), (c, d) = ref.position(text, start, encoding), ref.position(text, end, encoding)
    return types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(line=a, character=b), end=types.Position(line=c, character=d)),
        text=insert)


@st.composite
def edits(draw: st.DrawFn) -> tuple[str, int, int, str]:
    text = draw(TEXTS)
    offsets = [i for i in range(len(text) + 1) if addressable(text, i)]
    start = draw(st.sampled_from(offsets))
    end = draw(st.sampled_from([i for i in offsets if i >= start]))
    return text, start, end, draw(TEXTS)


@pytest.mark.parametrize("encoding", ref.ENCODINGS)
@given(edit=edits())
def test_an_edit_gives_the_clients_text(encoding: str, edit: tuple[str, int, int, str]) -> None:
    text, start, end, insert = edit
    applied = apply_change(text, change(text, start, end, insert, encoding), encoding)
    assert applied == text[:start] + insert + text[end:]


@pytest.mark.parametrize("encoding", ref.ENCODINGS)
@given(text=TEXTS, steps=st.lists(st.tuples(st.floats(0, 1), st.floats(0, 1), TEXTS), max_size=6))
def test_a_sequence_of_edits_in_one_notification(encoding: str, text: str,
                                                  steps: list[tuple[float, float, str]]) -> None:
    expected, changes = text, []
    for start_fraction, length_fraction, insert in steps:
        offsets = [i for i in range(len(expected) + 1) if addressable(expected, i)]
        start = offsets[int(start_fraction * (len(offsets) - 1))]
        later = [i for i in offsets if i >= start]
        end = later[int(length_fraction * (len(later) - 1))]
        changes.append(change(expected, start, end, insert, encoding))
        expected = expected[:start] + insert + expected[end:]
    assert apply_changes(text, changes, encoding) == expected


def test_an_edit_below_a_form_feed_or_u2028_lands_where_the_editor_put_it() -> None:
    # pygls's str.splitlines counted the \f and the U+2028 as line ends and put this edit two lines too low
    text = "role A { // page\f break\n  // a\u2028b\n  x;\n}\n"
    edit = types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(line=2, character=2), end=types.Position(line=2, character=3)),
        text="self.y() > 0")
    assert apply_change(text, edit) == text.replace("x;", "self.y() > 0;")


def test_lone_cr_ends_a_line() -> None:
    text = "a\rb\r\nc"
    edit = types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(line=1, character=0), end=types.Position(line=2, character=1)),
        text="X")
    assert apply_change(text, edit) == "a\rX"


def test_positions_past_the_end_are_clamped_and_backward_ranges_turned() -> None:
    text = "ab\r\ncd"
    past_line = types.Position(line=0, character=99)  # the end of line 0, before its \r\n
    past_text = types.Position(line=9, character=0)
    edit = types.TextDocumentContentChangePartial(range=types.Range(start=past_line, end=past_line), text="!")
    assert apply_change(text, edit) == "ab!\r\ncd"
    edit = types.TextDocumentContentChangePartial(range=types.Range(start=past_text, end=past_text), text="!")
    assert apply_change(text, edit) == "ab\r\ncd!"
    backward = types.Range(start=types.Position(line=1, character=1), end=types.Position(line=0, character=1))
    assert apply_change(text, types.TextDocumentContentChangePartial(range=backward, text="")) == "ad"


def test_a_position_inside_a_character_counts_as_after_it() -> None:
    text = "😀x"  # two UTF-16 units, four UTF-8 bytes
    for encoding, inside in (("utf-16", 1), ("utf-8", 2)):
        at = types.Position(line=0, character=inside)
        edit = types.TextDocumentContentChangePartial(range=types.Range(start=at, end=at), text="!")
        assert apply_change(text, edit, encoding) == "😀!x"


def test_a_whole_document_change_replaces_everything() -> None:
    whole = types.TextDocumentContentChangeWholeDocument(text="new\u2028text")
    assert apply_changes("old\ftext", [whole]) == "new\u2028text"
