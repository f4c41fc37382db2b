"""Pathological inputs: deep nesting, long inputs; the parser stays linear and never raises."""

from __future__ import annotations

import pytest

from rdcd_core.syntax import ast, parse
from rdcd_core.syntax.builder import MAX_DEPTH, MAX_HEIGHT
from tests.syntax.helpers import check_spans

N = 5000


@pytest.mark.parametrize(("expr", "code"), [
    ("+".join(["1"] * N), "E016"),
    ("(" * N + "1" + ")" * N, "E015"),
    ("-" * N + "1", "E015"),
    ("!" * N + "a", "E015"),
    ("(" * 70 + " + ".join(["(" * 40 + "1" + ")" * 40] * N) + ")" * 70, "E015"),  # too high inside
    ("(" * 60 + " + ".join(["(" * 30 + "1" + ")" * 30] * N) + ")" * 60, "E016"),
    (" + ".join(["(" + " + ".join(["1"] * 5) + ")"] * N), "E016"),
])
def test_too_deep_expressions_are_reported_and_left_out(expr: str, code: str) -> None:
    text = f"role A {{ x == {expr}; y; }}\ndeployment {{ A }}"
    result = parse(text)
    assert [d.code for d in result.diagnostics] == [code]
    (role,) = result.program.roles
    assert [type(m).__name__ for m in role.members] == ["Invariant"]
    expr = role.members[0].expr
    assert expr == ast.NameRef(ast.Name("y", expr.span), expr.span)
    repr(result.program)  # the tree left is shallow enough for recursive code


def test_nesting_up_to_the_limit_is_fine() -> None:
    depth = MAX_DEPTH - 10
    text = f"role A {{ {'(' * depth}1{')' * depth} > 0; }}\ndeployment {{ A }}"
    assert parse(text).diagnostics == []


def test_a_flat_chain_is_not_nesting() -> None:
    """a + b + c + … is one level of nesting, however long: 100 terms (issue 10) and more are fine,
    nested to the limit too, up to the height the later passes take (MAX_HEIGHT, then E016)."""
    for terms in (100, MAX_HEIGHT - MAX_DEPTH):
        chain = " + ".join(["1"] * terms)
        deep = MAX_DEPTH - 3
        for expr in (chain, f"{'(' * deep}{chain}{')' * deep}", f"{'-' * deep}({chain})"):
            text = f"role A {{ {expr} > 0; }}\ndeployment {{ A }}"
            assert parse(text).diagnostics == [], expr[:50]
    messages = [d.message for d in parse(f"role A {{ {' + '.join(['1'] * 500)} > 0; }}\ndeployment {{ A }}")
                .diagnostics]
    assert len(messages) == 1 and f"more than {MAX_HEIGHT} operations one inside another" in messages[0]
    assert "nested" not in messages[0]


def test_an_else_if_chain_is_not_nesting() -> None:
    chain = " else ".join(f"if (x == {k % 100}) self.setLed({k % 100});" for k in range(MAX_HEIGHT - 10))
    assert parse(f"role A {{ startup f() {{ {chain} }} }}\ndeployment {{ A }}").diagnostics == []
    chain = " else ".join(f"if (x == {k % 100}) self.setLed({k % 100});" for k in range(N))
    result = parse(f"role A {{ startup f() {{ {chain} }} }}\ndeployment {{ A }}")
    assert [d.code for d in result.diagnostics] == ["E016"]
    assert "each 'else if' counts" in result.diagnostics[0].message


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
