"""Invalid programs: every error is reported at the offending token, with code, line and message."""

from __future__ import annotations

import pytest

from rdcd_core.diagnostics import Severity, all_codes
from rdcd_core.source import LineIndex
from rdcd_core.syntax import ast, parse
from tests.conftest import EXAMPLES
from tests.syntax.helpers import check_spans, errors


def test_figure5_verbatim_has_one_error_at_the_stray_brace() -> None:
    text = (EXAMPLES / "figure5_verbatim.rdcd").read_text(encoding="utf-8")
    result = parse(text)
    lines = LineIndex(text)
    assert 1 <= len(result.diagnostics) <= 2
    first = result.diagnostics[0]
    assert lines.line_col(first.span.start).line + 1 in (40, 41)
    assert "'}'" in first.message and "too many" in first.message
    assert first.related and lines.line_col(first.related[0].span.start).line + 1 == 40
    program = result.program
    assert [r.name.text for r in program.roles] == ["Wheel", "RightWheel", "LeftWheel", "Reverse", "Axle"]
    wheel, right, left, reverse, axle = program.roles
    assert len(wheel.members) == 7 and len(right.members) == 3 and len(left.members) == 3
    assert reverse.modifies.text == "Wheel"
    assert isinstance(axle.members[0], ast.Invariant)
    steer = axle.members[1]
    assert isinstance(steer, ast.MethodDecl) and steer.name.text == "steer"
    assert [n.text for n in program.deployment.roles] == ["RightWheel", "LeftWheel", "Axle"]
    check_spans(text, program)


@pytest.mark.parametrize(("text", "code", "line", "message"), [
    ("role A {\n  self.x() > 0\n  startup f() { }\n}\ndeployment { A }",
     "E004", 2, "expected ';' after the invariant"),
    ("role A {\n  constant c := 3\n}\ndeployment { A }",
     "E004", 2, "expected ';' after the constant definition"),
    ("role A {\n  abstract constant a, b\n}\ndeployment { A }",
     "E004", 2, "expected ';' after the abstract constant list"),
    ("role A {\n  startup f() { self.sleep() }\n}\ndeployment { A }",
     "E004", 2, "expected ';' after the call"),
    ("role A extends {\n}\ndeployment { A }", "E007", 1, "expected a role name after 'extends'"),
    ("role A modifies {\n}\ndeployment { A }", "E007", 1, "expected a role name after 'modifies'"),
    ("role {\n}\ndeployment { A }", "E007", 1, "expected a role name after 'role'"),
    ("role A { constant := 1; }\ndeployment { A }", "E007", 1, "expected a constant name after 'constant'"),
    ("role A { self.(); }\ndeployment { A }", "E007", 1, "expected a method name after '.'"),
    ("role A { }\ndeployment { A, }", "E007", 2, "expected a role name after ','"),
    ("role A { }\n}\ndeployment { A }", "E005", 2, "unmatched '}'"),
    ("role A { a) ; }\ndeployment { A }", "E005", 1, "unmatched ')'"),
    ("role A {\n  sizeof(self.total_connected() > 0;\n}\ndeployment { A }",
     "E012", 2, "expected ')' to close the arguments of 'sizeof' opened on line 2"),
    ("role A {\n  startup f() {\n    self.sleep();\n\n  command g() { }\n}\ndeployment { A }",
     "E012", 3, "expected '}' to close method 'f' opened on line 2"),
    ("role A {\n  startup f() {\n    if (a > 0 self.sleep();\n  }\n}\ndeployment { A }",
     "E012", 3, "expected ')' to close the 'if' condition"),
    ("role A {\n  self.x() > 0;\n", "E006", 3, "the '{' of role 'A' on line 1 is never closed"),
    ("role A { }\n", "E008", 2, "missing deployment"),
    ("role A { }\nself.sleep();\ndeployment { A }", "E009", 2, "outside of a role"),
    ("role A { startup go(); }\ndeployment { A }", "E010", 1, "method 'go' has no body"),
    ("role A {\n  0 < self.x() < 5;\n}\ndeployment { A }", "E011", 2, "comparisons cannot be chained"),
    ("role A { startup go() {\n ; else ; } }\ndeployment { A }", "E013", 2, "'else' without a matching 'if'"),
    ("deployment { A }\nrole A { }", "E014", 2, "the deployment must come last"),
    ("role A { self.x() > > 1; }\ndeployment { A }", "E003", 1, "unexpected '>': expected an expression"),
    ("role A { constant c := ; }\ndeployment { A }", "E003", 1, "expected the constant's value after ':='"),
    ("role A {\n  self.x() # 1;\n}\ndeployment { A }", "E001", 2, "unexpected character '#'"),
    ("role A {\n  self.x() = 1;\n}\ndeployment { A }", "E001", 2, "use ':=' to define a constant or '=='"),
    ("role A { }\n/* open\ndeployment { A }", "E002", 2, "unterminated comment"),
])
def test_single_error(text: str, code: str, line: int, message: str) -> None:
    found = errors(text)
    assert len(found) == 1, found
    assert found[0][0] == code and found[0][1] == line, found
    assert message in found[0][2], found


def test_all_independent_errors_are_reported() -> None:
    text = ("role A extends {\n"
            "  constant c := 1\n"
            "  startup go() { self.sleep() }\n"
            "}\n"
            "role B { sizeof(self.total_connected() > 0; }\n"
            "role C { 1 +; }\n"
            "deployment { A B C }\n")
    found = errors(text)
    assert [(code, line) for code, line, _ in found] == [
        ("E007", 1), ("E004", 2), ("E004", 3), ("E012", 5), ("E003", 6), ("E003", 7)]
    program = parse(text).program
    assert [r.name.text for r in program.roles] == ["A", "B", "C"]
    assert [n.text for n in program.deployment.roles] == ["A", "B", "C"]


def test_members_after_an_error_survive() -> None:
    text = "role A {\n  a == ;\n  constant c := 1;\n  command go() { self.sleep(); }\n}\ndeployment { A }"
    result = parse(text)
    assert len(result.diagnostics) == 1
    kinds = [type(m).__name__ for m in result.program.roles[0].members]
    assert kinds[-2:] == ["ConstantDef", "MethodDecl"]


def test_statements_after_an_error_survive() -> None:
    text = "role A { startup go() { self.a(; self.b(); if (x) self.c(); } }\ndeployment { A }"
    result = parse(text)
    assert len(result.diagnostics) == 1
    body = result.program.roles[0].members[0].body
    assert isinstance(body.statements[-1], ast.IfStmt)


def test_diagnostics_are_errors_with_registered_codes() -> None:
    registered = {info.code for info in all_codes()}
    text = "role { a b c ) } } }\nrole B { ( ( ( \n"
    for diagnostic in parse(text).diagnostics:
        assert diagnostic.severity is Severity.ERROR
        assert diagnostic.code in registered


@pytest.mark.parametrize("info", [i for i in all_codes() if i.code.startswith("E0")], ids=lambda i: i.code)
def test_each_code_example_triggers_its_code(info) -> None:  # noqa: ANN001
    assert info.code in [d.code for d in parse(info.example).diagnostics]


@pytest.mark.parametrize("text", ["", "}", "{{{{", "((((", "role", "abstract", "deployment",
                                  "deployment {", "role A", "role A {", "/*", "@@@", "else", "if (",
                                  "role A { startup go() { if (x) } }", "role A { x := 1; }"])
def test_degenerate_inputs(text: str) -> None:
    result = parse(text)
    assert result.diagnostics
    check_spans(text, result.program)
