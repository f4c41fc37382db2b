from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.source import (
    LineIndex,
    count_line_breaks,
    newline_of,
    normalize_newlines,
    split_lines,
    visible,
)
from tests import line_reference as ref


def test_line_col_of_offsets() -> None:
    index = LineIndex("ab\ncd\n\nx")
    assert (index.line_col(0).line, index.line_col(0).column) == (0, 0)
    assert (index.line_col(4).line, index.line_col(4).column) == (1, 1)
    assert (index.line_col(7).line, index.line_col(7).column) == (3, 0)
    assert index.line_text(1) == "cd"
    assert index.line_count == 4


@given(st.text(alphabet="ab\n", max_size=40), st.integers(0, 40))
def test_offset_round_trip(text: str, offset: int) -> None:
    index = LineIndex(text)
    offset = min(offset, len(text))
    position = index.line_col(offset)
    assert index.offset(position.line, position.column) == offset


# -- one definition of a line: the LSP's --------------------------------------------------------------

# every line-break-like character, a few letters, a non-BMP character and a two-unit UTF-16 one
ALPHABET = st.sampled_from([*ref.LINE_BREAK_LIKE, "a", "b", " ", "é", "😀", "\t"])
TEXTS = st.lists(ALPHABET, max_size=30).map("".join)


def test_only_lf_crlf_and_lone_cr_end_a_line() -> None:
    text = "a\nb\r\nc\rd\x0be\x0cf\x1cg\x1dh\x1ei\x85j\u2028k\u2029l"
    index = LineIndex(text)
    assert index.line_count == 4
    last = "d\x0be\x0cf\x1cg\x1dh\x1ei\x85j\u2028k\u2029l"
    assert [index.line_text(n) for n in range(4)] == ["a", "b", "c", last]
    assert index.line_col(text.index("l")).line == 3
    assert split_lines(text) == ["a", "b", "c", text[text.index("d"):]]


def test_lone_cr_moves_to_the_next_line() -> None:
    index = LineIndex("role A {\r  x\r}")
    assert index.line_col(11).line == 1 and index.line_col(11).column == 2
    assert index.line_col(13).line == 2 and index.line_col(13).column == 0
    assert index.line_text(1) == "  x"


def test_crlf_is_one_break_and_no_position_lands_inside_it() -> None:
    index = LineIndex("ab\r\ncd")
    assert index.line_starts == [0, 4]
    assert index.line_text(0) == "ab"
    assert index.offset(0, 99) == 2  # the end of the line is before its \r
    assert index.line_end(0) == 2
    assert index.offset(1, 0) == 4
    empty = LineIndex("\r\n\r\n")
    assert [empty.line_text(n) for n in range(3)] == ["", "", ""]
    assert empty.offset(1, 5) == 2


@given(TEXTS)
def test_line_index_agrees_with_the_reference(text: str) -> None:
    index = LineIndex(text)
    expected = ref.lines(text)
    assert index.line_count == len(expected)
    assert [index.line_text(n) for n in range(index.line_count)] == [text[a:b] for a, b in expected]
    assert split_lines(text) == [text[a:b] for a, b in expected]
    assert count_line_breaks(text) == len(expected) - 1
    for number, (start, end) in enumerate(expected):
        for offset in range(start, end + 1):
            assert (index.line_col(offset).line, index.line_col(offset).column) == (number, offset - start)
            assert index.offset(number, offset - start) == offset


@given(TEXTS)
def test_split_lines_keeping_ends_joins_back(text: str) -> None:
    pieces = split_lines(text, keepends=True)
    assert "".join(pieces) == text
    assert all(piece for piece in pieces)
    assert len(pieces) == count_line_breaks(text) + (0 if not text or text.endswith(("\n", "\r")) else 1)


@given(TEXTS, st.sampled_from(["\n", "\r\n", "\r"]))
def test_normalize_newlines(text: str, newline: str) -> None:
    normal = normalize_newlines(text, newline)
    assert split_lines(normal) == split_lines(text)
    assert count_line_breaks(normal) == normal.count(newline)
    assert newline_of(normal) == (newline if count_line_breaks(text) else "\n")


def test_newline_of_is_the_first_break() -> None:
    assert newline_of("a\r\nb\nc") == "\r\n"
    assert newline_of("a\rb\r\n") == "\r"
    assert newline_of("a\u2028b\x0cc") == "\n"


@given(TEXTS)
def test_visible_keeps_columns_and_shows_no_break(text: str) -> None:
    line = visible(text)
    assert len(line) == len(text)
    assert len(line.splitlines()) <= 1  # nothing left that any terminal or splitlines breaks at
    assert all(char == "\t" or char.isprintable() for char in line)
