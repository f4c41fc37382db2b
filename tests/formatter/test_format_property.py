"""Over generated programs with random layout and comments: formatting keeps the AST and every
comment, and formatting twice changes nothing."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.formatter import format_text
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import parse

NAMES = ["a", "b", "speed", "Wheel", "EAST", "UP_DOWN", "EVENT_PROXIMITY_2"]
SEPARATORS = [" ", " ", " ", "\n", "\n\n", "\t", "\n    ", " /* c */ ", " // note\n", "\n/* x\n  y */\n"]


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
        return [draw(st.sampled_from(["-", "!"])), *primary(draw, depth - 1)]
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
    assert [c.text for c in again.program.comments] == [c.text for c in parsed.program.comments]
    assert format_text(once) == once
