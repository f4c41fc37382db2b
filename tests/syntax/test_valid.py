"""Valid programs: every construct of the grammar (docs/language.md) and its AST."""

from __future__ import annotations

import pytest

from rdcd_core.syntax import ast, parse
from tests.conftest import EXAMPLES
from tests.syntax.helpers import check_spans, invariant, members, parse_ok, statements, text_of


@pytest.mark.parametrize("name", ["obstacle_avoidance.rdcd", "snake_wave.rdcd"])
def test_examples_parse_clean(name: str) -> None:
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    program = parse_ok(text)
    check_spans(text, program)
    assert program.deployment is not None


def test_obstacle_avoidance_shape() -> None:
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    program = parse_ok(text)
    assert [r.name.text for r in program.roles] == ["Wheel", "RightWheel", "LeftWheel", "Reverse", "Axle"]
    wheel, right, _, reverse, axle = program.roles
    assert wheel.is_abstract and wheel.extends is None and wheel.modifies is None
    assert right.extends.text == "Wheel" and not right.is_abstract
    assert reverse.modifies.text == "Wheel" and reverse.members == ()
    assert [n.text for n in program.deployment.roles] == ["RightWheel", "LeftWheel", "Axle"]
    assert len(program.comments) == 3
    steer = axle.members[1]
    assert isinstance(steer, ast.MethodDecl) and steer.kind is ast.MethodKind.BEHAVIOR
    (outer,) = steer.body.statements
    assert isinstance(outer, ast.IfStmt) and isinstance(outer.else_body, ast.CallStmt)


def test_role_headers() -> None:
    text = "abstract role A { }\nrole B extends A { }\nrole M modifies B { }\nrole C { }\ndeployment { B, C }"
    program = parse_ok(text)
    a, b, m, c = program.roles
    assert a.is_abstract and text_of(text, a.abstract_span) == "abstract"
    assert text_of(text, a) == "abstract role A { }"
    assert text[a.header_span.start:a.header_span.end] == "abstract role A {"
    assert b.extends.text == "A" and b.modifies is None and b.abstract_span is None
    assert m.modifies.text == "B" and m.extends is None
    assert c.extends is None and c.modifies is None
    assert text_of(text, program.deployment) == "deployment { B, C }"


def test_empty_deployment_and_empty_program_parts() -> None:
    program = parse_ok("deployment { }")
    assert program.roles == () and program.deployment.roles == ()


def test_constants() -> None:
    abstract, definition, negative = members(
        "abstract constant a, b_2, C;\nconstant x := 300;\nconstant y := -(1 + 2);")
    assert isinstance(abstract, ast.AbstractConstants)
    assert [n.text for n in abstract.names] == ["a", "b_2", "C"]
    assert isinstance(definition, ast.ConstantDef) and definition.name.text == "x"
    assert definition.value == ast.IntLit(300, definition.value.span)  # range checks are semantic
    assert isinstance(negative.value, ast.Unary) and isinstance(negative.value.operand, ast.Paren)


def test_methods_and_modifiers() -> None:
    source = ("abstract startup s();\nbehavior b() { }\ncommand c() { ; }\nplain() { }\n"
              "abstract command ac();\nabstract p();")
    s, b, c, plain, ac, p = members(source)
    assert s.is_abstract and s.kind is ast.MethodKind.STARTUP and s.body is None
    assert b.kind is ast.MethodKind.BEHAVIOR and b.body.statements == ()
    assert c.kind is ast.MethodKind.COMMAND and isinstance(c.body.statements[0], ast.EmptyStmt)
    assert plain.kind is ast.MethodKind.PLAIN and plain.modifiers == ()
    assert [m.keyword for m in ac.modifiers] == ["abstract", "command"] and ac.body is None
    assert p.is_abstract and p.kind is ast.MethodKind.PLAIN


def test_invariants_are_expressions() -> None:
    first, second = members("self.center_position == EAST_WEST;\nsizeof(self.total_connected()) >= 1;")
    assert isinstance(first, ast.Invariant) and isinstance(second, ast.Invariant)
    query = first.expr.left
    assert isinstance(query, ast.SelfCall) and not query.has_parens and query.args == ()


def test_calls() -> None:
    expr = invariant("connected_role(DOWN, Wheel) + sizeof(self.connected(UP)) + self.y()")
    left, y = expr.left, expr.right
    function, size = left.left, left.right
    assert isinstance(function, ast.FunctionCall) and function.name.text == "connected_role"
    assert [a.name.text for a in function.args] == ["DOWN", "Wheel"]
    assert isinstance(size.args[0], ast.SelfCall) and size.args[0].has_parens
    assert isinstance(y, ast.SelfCall) and y.has_parens and y.args == ()


def test_global_call_and_block_arguments() -> None:
    (handler, global_call) = statements(
        "self.handleEvent(EVENT_PROXIMITY_0, { self.sleep(); Wheel.stop(); }); Segment.flash();")
    call = handler.call
    assert isinstance(call, ast.SelfCall) and call.name.text == "handleEvent"
    event, block = call.args
    assert isinstance(event, ast.NameRef) and isinstance(block, ast.Block)
    inner = block.statements[1].call
    assert isinstance(inner, ast.GlobalCall) and inner.role.text == "Wheel" and inner.name.text == "stop"
    assert isinstance(global_call.call, ast.GlobalCall) and global_call.call.args == ()


def test_statements() -> None:
    empty, call, if_stmt = statements("; self.sleep(); if (self.x() > 0) { self.sleep(); } else ;")
    assert isinstance(empty, ast.EmptyStmt)
    assert isinstance(call, ast.CallStmt)
    assert isinstance(if_stmt.then_body, ast.Block) and isinstance(if_stmt.else_body, ast.EmptyStmt)


def test_dangling_else_binds_to_nearest_if() -> None:
    (outer,) = statements("if (a) if (b) self.x(); else self.y();")
    assert outer.else_body is None
    inner = outer.then_body
    assert isinstance(inner, ast.IfStmt) and isinstance(inner.else_body, ast.CallStmt)


def test_nested_if_else_chains() -> None:
    (first,) = statements("if (a) { if (b) ; } else if (c) self.x(); else { self.y(); }")
    assert isinstance(first.then_body, ast.Block)
    second = first.else_body
    assert isinstance(second, ast.IfStmt) and isinstance(second.else_body, ast.Block)


@pytest.mark.parametrize(("source", "shape"), [
    ("a || b && c", ("||", "a", ("&&", "b", "c"))),
    ("a && b || c", ("||", ("&&", "a", "b"), "c")),
    ("a == b && c != d", ("&&", ("==", "a", "b"), ("!=", "c", "d"))),
    ("a < b == c >= d", ("==", ("<", "a", "b"), (">=", "c", "d"))),
    ("a + b < c - d", ("<", ("+", "a", "b"), ("-", "c", "d"))),
    ("a - b + c", ("+", ("-", "a", "b"), "c")),
    ("a == b == c", ("==", ("==", "a", "b"), "c")),
    ("a <= b", ("<=", "a", "b")),
    ("a > b", (">", "a", "b")),
    ("- a + b", ("+", ("-", "a"), "b")),
    ("!a && !!b", ("&&", ("!", "a"), ("!", ("!", "b")))),
    ("- - 1", ("-", ("-", 1))),
    ("(a || b) && c", ("&&", ("()", ("||", "a", "b")), "c")),
])
def test_operators_and_precedence(source: str, shape: tuple) -> None:
    assert _shape(invariant(source)) == shape


def _shape(expr: ast.Expr) -> object:
    if isinstance(expr, ast.Binary):
        return (expr.op, _shape(expr.left), _shape(expr.right))
    if isinstance(expr, ast.Unary):
        return (expr.op, _shape(expr.operand))
    if isinstance(expr, ast.Paren):
        return ("()", _shape(expr.expr))
    if isinstance(expr, ast.NameRef):
        return expr.name.text
    if isinstance(expr, ast.IntLit):
        return expr.value
    raise AssertionError(expr)


def test_exact_spans() -> None:
    text = "role A {\n  x + 1 >= -y;\n  startup go() { if (x) self.a(1); else B.c(); }\n}\ndeployment { A }"
    program = parse_ok(text)
    check_spans(text, program)
    inv, method = program.roles[0].members
    assert text_of(text, inv) == "x + 1 >= -y;"
    assert text_of(text, inv.expr) == "x + 1 >= -y"
    assert text[inv.expr.op_span.start:inv.expr.op_span.end] == ">="
    assert text_of(text, inv.expr.left) == "x + 1"
    assert text_of(text, inv.expr.right) == "-y"
    assert text_of(text, method) == "startup go() { if (x) self.a(1); else B.c(); }"
    assert text_of(text, method.modifiers[0]) == "startup"
    assert text_of(text, method.name) == "go"
    if_stmt = method.body.statements[0]
    assert text_of(text, if_stmt) == "if (x) self.a(1); else B.c();"
    assert text[if_stmt.else_span.start:if_stmt.else_span.end] == "else"
    assert text_of(text, if_stmt.then_body) == "self.a(1);"
    assert text_of(text, if_stmt.then_body.call) == "self.a(1)"
    assert text_of(text, if_stmt.else_body.call) == "B.c()"
    assert program.span.start == 0 and program.span.end == len(text)


def test_parens_are_kept() -> None:
    expr = invariant("((a))")
    assert isinstance(expr, ast.Paren) and isinstance(expr.expr, ast.Paren)
    assert ast.unparen(expr) == expr.expr.expr


def test_comments_of_both_kinds() -> None:
    text = "// head\nrole A { /* in\n side */ a; // tail\n}\n/**/deployment { A } //"
    program = parse_ok(text)
    assert [c.text for c in program.comments] == ["// head", "/* in\n side */", "// tail", "/**/", "//"]
    for comment in program.comments:
        assert text_of(text, comment) == comment.text


def test_keywords_are_reserved_but_prefixes_are_names() -> None:
    (inv,) = members("roles + selfish + iff;")
    assert _shape(inv.expr) == ("+", ("+", "roles", "selfish"), "iff")
    assert parse("role role { }\ndeployment { }").diagnostics


def test_integer_literals_as_written() -> None:
    assert invariant("99999").value == 99999
    assert invariant("007").value == 7
    huge = invariant("9" * 5000)
    assert huge.value > 127  # too long to convert exactly; still out of range for semantics


def test_parse_result_is_reusable_and_pure() -> None:
    text = (EXAMPLES / "snake_wave.rdcd").read_text(encoding="utf-8")
    assert parse(text).program == parse(text).program
