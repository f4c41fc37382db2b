from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.source import LineIndex


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
