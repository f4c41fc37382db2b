"""Over generated programs with random layout and comments: formatting keeps the AST, the tokens
and every comment, and formatting twice changes nothing. Layouts use every line break (\n, \r\n,
a lone \r) and comments hold every other line-break-like character (form feed, U+2028, ...)."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.formatter import format_text
from rdcd_core.source import count_line_breaks, newline_of, normalize_newlines
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import parse
from rdcd_core.syntax.tables import tables

NAMES = ["a", "b", "speed", "Wheel", "EAST", "UP_DOWN", "EVENT_PROXIMITY_2"]
SEPARATORS = [" ", " ", " ", "\n", "\n\n", "\t", "\n    ", " /* c */ ", " // note\n", "\n/* x\n  y */\n",
              "\r\n", "\r", "\r\r", "\r\n\r\n", "\f", " \f\n", " // note\r", " // n\r\n",
              "\r/* x\r\n y\r z */\r",
              # characters str.splitlines (and some editors) break at, which are no line breaks in RDCD
              " // a\u2028b\x85c\n", " /* \v\x1c\x1d\x1e\u2029 */ ", " // \f\r", "\n// page\f\n",
              " /*\u2028*/ ", " // ends in U+2029\u2029\n", "\ufeff"]
OPERATOR_PAIRS = {"--", "++", "!=", "==", "<=", ">=", "&&", "||", ":="}  # would read as one operator


def primary(draw: st.DrawFn, depth: int) -> list[str]:
    choice = draw(st.integers(0, 6 if depth > 0 else 3))
    if choice == 0:
        return [str(draw(st.integers(0, 100)))]
    if choice == 1:
        return [draw(st.sampled_from(NAMES))]
    if choice == 2:
        return ["self", ".", draw(st.sampled_from(["y", "center_position"]))]
    if choice == 3:
        return ["sizeof", "(", "self", ".", "total_connected", "(", ")", ")"]
    if choice == 4:
        return ["(", *expression(draw, depth - 1), ")"]
    if choice == 5:
        deeper = depth - 1 if draw(st.booleans()) else depth  # "- -x" as often as "-(x)"
        return [draw(st.sampled_from(["-", "!"])), *primary(draw, deeper)]
    return ["connected_role", "(", "DOWN", ",", "Wheel", ")"]


def additive(draw: st.DrawFn, depth: int) -> list[str]:
    tokens = primary(draw, depth)
    for _ in range(draw(st.integers(0, 2))):
        tokens += [draw(st.sampled_from(["+", "-"])), *primary(draw, depth)]
    return tokens


def expression(draw: st.DrawFn, depth: int) -> list[str]:
    tokens = additive(draw, depth)
    if draw(st.booleans()):
        tokens += [draw(st.sampled_from(["<", ">", "<=", ">="])), *additive(draw, depth)]
    for _ in range(draw(st.integers(0, 2))):
        tokens += [draw(st.sampled_from(["==", "!=", "&&", "||"])), *additive(draw, depth)]
    return tokens


def statement(draw: st.DrawFn, depth: int) -> list[str]:
    choice = draw(st.integers(0, 5 if depth > 0 else 2))
    if choice == 0:
        return [";"]
    if choice == 1:
        return ["self", ".", "turnTowards", "(", *expression(draw, 1), ")", ";"]
    if choice == 2:
        return ["Wheel", ".", "stop", "(", ")", ";"]
    if choice == 3:
        tokens = ["if", "(", *expression(draw, 1), ")", *statement(draw, depth - 1)]
        if draw(st.booleans()):
            tokens += ["else", *statement(draw, depth - 1)]
        return tokens
    if choice == 4:
        return ["{", *block_body(draw, depth - 1), "}"]
    return ["self", ".", "handleEvent", "(", "EVENT_PROXIMITY_1", ",", "{", *block_body(draw, depth - 1), "}",
            ")", ";"]


def block_body(draw: st.DrawFn, depth: int) -> list[str]:
    tokens: list[str] = []
    for _ in range(draw(st.integers(0, 3))):
        tokens += statement(draw, depth)
    return tokens


def member(draw: st.DrawFn) -> list[str]:
    choice = draw(st.integers(0, 4))
    if choice == 0:
        return ["abstract", "constant", "a", ",", "b", ";"]
    if choice == 1:
        return ["constant", "speed", ":=", *expression(draw, 1), ";"]
    if choice == 2:
        return [*expression(draw, 2), ";"]
    if choice == 3:
        return ["abstract", "command", "stop", "(", ")", ";"]
    kind = draw(st.sampled_from([[], ["startup"], ["behavior"], ["command"]]))
    return [*kind, "go", "(", ")", "{", *block_body(draw, 2), "}"]


@st.composite
def programs(draw: st.DrawFn) -> str:
    tokens: list[str] = []
    for index in range(draw(st.integers(1, 3))):
        header = draw(st.sampled_from([["role"], ["abstract", "role"]]))
        tokens += [*header, f"R{index}"]
        if draw(st.booleans()):
            tokens += [draw(st.sampled_from(["extends", "modifies"])), "Wheel"]
        tokens.append("{")
        for _ in range(draw(st.integers(0, 3))):
            tokens += member(draw)
        tokens.append("}")
    tokens += ["deployment", "{", "R0", "}"]
    text = draw(st.sampled_from(["", "// top\n", "/* top */"]))
    for token in tokens:
        text += token + draw(st.sampled_from(SEPARATORS))
    return text


def lexed(text: str) -> list:
    return tables().lexer.lex(text).tokens


@given(programs())
def test_format_preserves_ast_comments_and_is_idempotent(text: str) -> None:
    parsed = parse(text)
    once = format_text(text)
    if once is None:
        assert parsed.diagnostics, "format_text refuses only texts with syntax errors"
        return
    again = parse(once)
    assert not again.diagnostics
    assert ast.strip_spans(again.program) == ast.strip_spans(parsed.program)
    newline = newline_of(text)
    assert [c.text for c in again.program.comments] == \
        [normalize_newlines(c.text, newline) for c in parsed.program.comments]
    assert format_text(once) == once


@given(programs())
def test_format_writes_the_texts_own_line_break_only(text: str) -> None:
    once = format_text(text)
    if once is None:
        return
    newline = newline_of(text)
    assert count_line_breaks(once) == once.count(newline), f"a line break other than {newline!r}"
    if newline != "\r":
        assert "\r" not in once.replace("\r\n", "")


@given(programs())
def test_format_keeps_the_tokens_and_never_glues_operators(text: str) -> None:
    once = format_text(text)
    if once is None:
        return
    before, after = lexed(text), lexed(once)
    assert [(t.type, t.value) for t in after] == [(t.type, t.value) for t in before]
    for left, right in zip(after, after[1:], strict=False):
        if left.end == right.start:
            assert left.value[-1] + right.value[0] not in OPERATOR_PAIRS, once[left.start:right.end]


@given(programs(), st.sampled_from(["\r\n", "\r"]))
def test_the_line_break_style_changes_nothing_else(text: str, newline: str) -> None:
    if not count_line_breaks(text):
        return  # nothing to tell the styles apart
    lf = normalize_newlines(text)
    formatted = format_text(lf)
    other = format_text(normalize_newlines(text, newline))
    assert (other is None) == (formatted is None)
    if formatted is not None:
        assert other == normalize_newlines(formatted, newline)
