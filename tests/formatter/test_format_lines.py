"""The formatter and the LSP's lines: a text keeps its own line break (CRLF stays CRLF, inside
block comments too), a lone \\r is a line break like any other, form feed and U+2028 are not, and
printing never glues two operators into what reads as one."""

from __future__ import annotations

import pytest

from rdcd_core.formatter import format_edits, format_range, format_text
from rdcd_core.source import Span, count_line_breaks, normalize_newlines
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import parse

PROGRAM = """role A {
  // first
  self.y() > 0;

  /* two
     lines */
  self.y() < 9; // trailing
}

deployment { A }
"""


def apply(text: str, edits: list) -> str:
    for edit in sorted(edits, key=lambda e: e.span.start, reverse=True):
        text = text[:edit.span.start] + edit.new_text + text[edit.span.end:]
    return text


@pytest.mark.parametrize("newline", ["\r\n", "\r"])
def test_a_formatted_text_stays_formatted_in_every_line_break_style(newline: str) -> None:
    assert format_text(PROGRAM) == PROGRAM
    text = normalize_newlines(PROGRAM, newline)
    assert format_text(text) == text
    assert format_edits(text) == []


def test_crlf_file_with_lf_and_cr_inside_a_block_comment_becomes_crlf_throughout() -> None:
    text = "role A {\r\n  /* a\nb\rc\r\n  */\r\n  self.y() > 0;\r\n}\r\ndeployment { A }\r\n"
    once = format_text(text)
    assert once is not None
    assert count_line_breaks(once) == once.count("\r\n")
    assert "/* a\r\nb\r\nc\r\n  */" in once
    assert format_text(once) == once


def test_lone_cr_file_neither_duplicates_nor_deletes_lines() -> None:
    # With \r counted as no line break, the comment was taken for a trailing one of the header
    # and the blank line vanished.
    text = "role A {\r  // c\r  self.y() > 0;\r\r  self.y() > 1;\r}\rdeployment { A }\r"
    assert format_text(text) == ("role A {\r  // c\r  self.y() > 0;\r\r  self.y() > 1;\r}\r\r"
                                 "deployment { A }\r")


@pytest.mark.parametrize("char", ["\f", "\v", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"])
def test_line_break_like_characters_in_comments_are_kept_and_end_no_line(char: str) -> None:
    text = (f"role A {{ // a{char}b\n  self.y() > 0; /* c{char}d */ self.y() > 1;\n"
            f"  // ends with it{char}\n}}\ndeployment {{ A }}\n")
    once = format_text(text)
    assert once is not None
    assert [c.text for c in parse(once).program.comments] == [c.text for c in parse(text).program.comments]
    assert f"role A {{ // a{char}b\n" in once  # still a trailing comment of the header line
    assert format_text(once) == once
    assert apply(text, format_edits(text) or []) == once


def test_form_feed_between_tokens_is_white_space() -> None:
    text = "role A {\f\n  self.y()\f> 0;\n}\n\fdeployment { A }\n"
    assert format_text(text) == "role A {\n  self.y() > 0;\n}\n\ndeployment { A }\n"


@pytest.mark.parametrize(("source", "printed"), [
    ("- -1", "- -1"), ("- - -x", "- - -x"), ("-(-1)", "-(-1)"), ("!-x", "!-x"), ("-!x", "-!x"),
    ("!!x", "!!x"), ("x - -1", "x - -1"), ("- -x - - -1", "- -x - - -1"),
])
def test_unary_operators_are_not_glued(source: str, printed: str) -> None:
    text = f"role A {{ constant k := {source}; }}\ndeployment {{ A }}\n"
    once = format_text(text)
    assert once == f"role A {{\n  constant k := {printed};\n}}\n\ndeployment {{ A }}\n"
    assert ast.strip_spans(parse(once).program) == ast.strip_spans(parse(text).program)


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_range_formatting_writes_the_texts_line_break(newline: str) -> None:
    text = normalize_newlines("role A{constant c:=1;}\n\nrole B{constant d:=2;}\ndeployment{A,B}\n", newline)
    edits = format_range(text, Span(0, 5))
    assert edits and all(e.span.end <= text.index("role B") for e in edits)
    changed = apply(text, edits)
    assert changed.startswith(normalize_newlines("role A {\n  constant c := 1;\n}\n", newline))
    assert count_line_breaks(changed) == changed.count(newline)


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_format_edits_split_only_at_line_breaks(newline: str) -> None:
    text = normalize_newlines("role A {\n  // x\u2028y\x85z\n  self.y()>0;\n}\n\ndeployment { A }\n", newline)
    edits = format_edits(text)
    assert edits is not None and len(edits) == 1
    assert text[edits[0].span.start:edits[0].span.end] == "  self.y()>0;" + newline
    assert apply(text, edits) == format_text(text)
