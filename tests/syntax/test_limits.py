"""Pathological inputs: deep nesting, long inputs; the parser stays linear and never raises."""

from __future__ import annotations

import pytest

from rdcd_core.syntax import ast, parse
from rdcd_core.syntax.builder import MAX_DEPTH
from tests.syntax.helpers import check_spans

N = 5000


@pytest.mark.parametrize("expr", [
    "+".join(["1"] * N),
    "(" * N + "1" + ")" * N,
    "-" * N + "1",
    "!" * N + "a",
])
def test_too_deep_expressions_are_reported_and_left_out(expr: str) -> None:
    text = f"role A {{ x == {expr}; y; }}\ndeployment {{ A }}"
    result = parse(text)
    assert [d.code for d in result.diagnostics] == ["E015"]
    (role,) = result.program.roles
    assert [type(m).__name__ for m in role.members] == ["Invariant"]
    expr = role.members[0].expr
    assert expr == ast.NameRef(ast.Name("y", expr.span), expr.span)
    repr(result.program)  # the tree left is shallow enough for recursive code


def test_nesting_up_to_the_limit_is_fine() -> None:
    depth = MAX_DEPTH - 10
    text = f"role A {{ {'(' * depth}1{')' * depth} > 0; }}\ndeployment {{ A }}"
    assert parse(text).diagnostics == []


def test_deep_if_chains() -> None:
    text = "role A { startup f() { " + "if (x) " * N + "; } }\ndeployment { A }"
    result = parse(text)
    assert [d.code for d in result.diagnostics] == ["E015"]
    assert result.program.roles[0].members == ()


@pytest.mark.parametrize("text", [
    "(" * N, "role A { " + "(" * N, "{" * N, "}" * N, ";" * N, "role A { " + "x " * N,
    "role A { startup f() { " + "self.f({ " * (N // 4), "role A { startup f() { " + "else " * N,
    "role A { startup f() { " + "if (" * N,
])
def test_long_malformed_inputs(text: str) -> None:
    result = parse(text)
    assert result.diagnostics
    check_spans(text, result.program)


def test_mistyped_operators_are_read_as_meant() -> None:
    text = "role A { constant c = 1; self.x() = 2; a & b; a | b; }\ndeployment { A }"
    result = parse(text)
    assert [d.code for d in result.diagnostics] == ["E001"] * 4
    constant, equal, conj, disj = result.program.roles[0].members
    assert isinstance(constant, ast.ConstantDef) and constant.value.value == 1
    assert equal.expr.op == "==" and conj.expr.op == "&&" and disj.expr.op == "||"
