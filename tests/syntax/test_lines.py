"""The lexer's idea of a line is the LSP's: a line comment ends at \\n, \\r\\n or a lone \\r and
nowhere else, and the lines diagnostics are reported on are those an editor shows."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.frontend import check_text
from rdcd_core.syntax.tables import tables
from tests import line_reference as ref


def lex(text: str) -> tuple[list[tuple[str, str]], list[str]]:
    result = tables().lexer.lex(text)
    return [(t.type, t.value) for t in result.tokens], [c.text for c in result.comments]


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_a_line_comment_ends_at_every_line_break(newline: str) -> None:
    tokens, comments = lex(f"a // note{newline}b")
    assert tokens == [("NAME", "a"), ("NAME", "b")]
    assert comments == ["// note"]


@pytest.mark.parametrize("char", ref.NOT_LINE_BREAKS)
def test_a_line_comment_runs_over_characters_that_are_no_line_break(char: str) -> None:
    tokens, comments = lex(f"a // x{char}b\nc")
    assert tokens == [("NAME", "a"), ("NAME", "c")]
    assert comments == [f"// x{char}b"]


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_block_comments_hold_line_breaks(newline: str) -> None:
    tokens, comments = lex(f"a /* x{newline}y{newline} */ b")
    assert tokens == [("NAME", "a"), ("NAME", "b")]
    assert comments == [f"/* x{newline}y{newline} */"]


@pytest.mark.parametrize("char", ["\v", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"])
def test_line_break_like_characters_in_code_are_bad_characters_on_their_own_line(char: str) -> None:
    text = f"role A {{\r  self.y() >{char} 0;\r}}\rdeployment {{ A }}\r"
    diagnostics = check_text(text).diagnostics
    assert [d.code for d in diagnostics] == ["E001"]
    assert ref.position(text, diagnostics[0].span.start, "utf-32") == (1, 12)


SNIPPETS = ["role A {", "}", "self.y() > 0", ";", "deployment { A }", "constant k := 1;", "// c", "/* c */",
            "@", "\v", "\u2028", "\x85", "\f", " "]
BREAKS = ["\n", "\r\n", "\r", "\r\r", "\n\r", ""]


@given(st.lists(st.tuples(st.sampled_from(SNIPPETS), st.sampled_from(BREAKS)), max_size=12))
def test_diagnostics_are_on_the_line_an_editor_shows(pieces: list[tuple[str, str]]) -> None:
    text = "".join(a + b for a, b in pieces)
    result = check_text(text)
    index = result.line_index
    for diagnostic in result.diagnostics:
        for offset in (diagnostic.span.start, diagnostic.span.end):
            at = index.line_col(offset)
            assert ref.position(text, offset, "utf-32") == (at.line, at.column)
