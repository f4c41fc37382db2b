"""Error recovery: one mistake gives one diagnostic, and the rest of the file is kept."""

from __future__ import annotations

import re

import pytest

from rdcd_core.syntax import ast, parse
from tests.conftest import EXAMPLES
from tests.syntax.helpers import errors

EXAMPLE_NAMES = ["obstacle_avoidance.rdcd", "snake_wave.rdcd"]


def role_names(text: str) -> list[str]:
    return [role.name.text for role in parse(text).program.roles]


@pytest.mark.parametrize("name", EXAMPLE_NAMES)
def test_every_prefix_gives_one_diagnostic(name: str) -> None:
    """What the editor sees while the file is typed from top to bottom."""
    source = (EXAMPLES / name).read_text(encoding="utf-8")
    for match in re.finditer(r"\S+", source):
        prefix = source[:match.end()]
        if match.end() == len(source.rstrip()):
            continue
        assert len(parse(prefix).diagnostics) == 1, prefix[-60:]


@pytest.mark.parametrize("name", EXAMPLE_NAMES)
@pytest.mark.parametrize("inserted", ["startup x() {", "if (x) {", "{", "(", "role ", "constant "])
def test_a_line_typed_anywhere_loses_no_role(name: str, inserted: str) -> None:
    source = (EXAMPLES / name).read_text(encoding="utf-8")
    expected = role_names(source)
    for match in re.finditer(r"\n", source):
        text = source[:match.end()] + inserted + source[match.end():]
        result = parse(text)
        assert 1 <= len(result.diagnostics) <= 2, text[match.end() - 30:match.end() + 30]
        assert [r.name.text for r in result.program.roles][:len(expected)] == expected


def test_unclosed_method_before_members_is_one_error() -> None:
    text = ("role A {\n  startup go() {\n    self.sleep();\n\n  self.center_position == EAST_WEST;\n"
            "  sizeof(self.total_connected()) == 1;\n  command stop() { }\n}\ndeployment { A }")
    assert [(code, line) for code, line, _ in errors(text)] == [("E012", 3)]  # the '}' belongs after line 3
    (message,) = [m for _, _, m in errors(text)]
    assert ("expected '}' to close method 'go' opened on line 2: keyword 'self' on line 5 starts a member"
            in message)
    kinds = [type(m).__name__ for m in parse(text).program.roles[0].members]
    assert kinds == ["MethodDecl", "Invariant", "Invariant", "MethodDecl"]


def test_missing_method_body_brace() -> None:
    text = "role A {\n  startup go()\n    self.sleep();\n  }\n}\ndeployment { A }"
    assert [(code, line) for code, line, _ in errors(text)] == [("E003", 2)]  # the body belongs after 'go()'
    method = parse(text).program.roles[0].members[0]
    assert isinstance(method, ast.MethodDecl) and len(method.body.statements) == 1


def test_broken_then_branch_keeps_the_if_and_its_else() -> None:
    text = "role A { startup go() { if (x) self.(1); else self.b(); self.c(); } }\ndeployment { A }"
    result = parse(text)
    assert len(result.diagnostics) == 1
    statements = result.program.roles[0].members[0].body.statements
    assert isinstance(statements[0], ast.IfStmt) and statements[0].else_body is not None
    assert isinstance(statements[-1], ast.CallStmt)


def test_garbage_between_roles_is_skipped_in_one_error() -> None:
    text = "role A { }\nthis is ( not { RDCD } at all ;\nrole B { }\ndeployment { A, B }"
    assert [code for code, _, _ in errors(text)] == ["E009"]
    assert role_names(text) == ["A", "B"]


def test_unclosed_role_is_closed_at_the_next_role() -> None:
    text = "role A {\n  x > 0;\n  startup go() { self.sleep();\nrole B { }\ndeployment { A, B }"
    assert [(code, line) for code, line, _ in errors(text)] == [("E012", 3)]
    assert role_names(text) == ["A", "B"]


def test_deployment_names_survive_errors() -> None:
    for text in ["role A { }\ndeployment { A B C }", "role A { }\ndeployment { A, B; C }",
                 "role A { }\ndeployment { A, ( B, C }"]:
        result = parse(text)
        assert len(result.diagnostics) == 1
        assert [n.text for n in result.program.deployment.roles] == ["A", "B", "C"]
