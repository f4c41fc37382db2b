"""Helpers shared by the syntax tests."""

from __future__ import annotations

from dataclasses import fields

from rdcd_core.source import LineIndex, Span
from rdcd_core.syntax import ast, parse


def parse_ok(text: str) -> ast.Program:
    result = parse(text)
    assert result.diagnostics == [], [d.message for d in result.diagnostics]
    return result.program


def members(body: str) -> tuple:
    """The members of role ``A { body }``."""
    return parse_ok(f"role A {{\n{body}\n}}\ndeployment {{ A }}").roles[0].members


def invariant(expr: str) -> ast.Expr:
    (member,) = members(expr + ";")
    assert isinstance(member, ast.Invariant)
    return member.expr


def statements(body: str) -> tuple:
    (method,) = members(f"startup go() {{ {body} }}")
    return method.body.statements


def text_of(source: str, node: object) -> str:
    span = node if isinstance(node, Span) else node.span
    return source[span.start:span.end]


def errors(text: str) -> list[tuple[str, int, str]]:
    """(code, 1-based line, message) of every diagnostic."""
    lines = LineIndex(text)
    return [(d.code, lines.line_col(d.span.start).line + 1, d.message) for d in parse(text).diagnostics]


_AST_TYPES = tuple(t for t in vars(ast).values()
                   if isinstance(t, type) and hasattr(t, "__dataclass_fields__"))


def check_types(program: ast.Program) -> None:
    """The tree holds only AST nodes and plain values (no parser tokens, lists or Lark trees)."""
    stack: list = [program]
    while stack:
        node = stack.pop()
        assert isinstance(node, _AST_TYPES), node
        for f in fields(node):
            value = getattr(node, f.name)
            items = value if isinstance(value, tuple) else (value,)
            for item in items:
                if isinstance(item, Span) or item is None or isinstance(item, (str, int, bool)):
                    continue
                stack.append(item)


def check_spans(text: str, program: ast.Program) -> None:
    """Every span lies in the text and inside its parent's span."""
    check_types(program)
    stack = [(program, program.span)]
    while stack:
        node, parent = stack.pop()
        span = node.span
        assert 0 <= span.start <= span.end <= len(text), (node, len(text))
        assert parent.start <= span.start and span.end <= parent.end, (node, parent)
        stack.extend((child, span) for child in ast.children(node))
    for comment in program.comments:
        assert 0 <= comment.span.start <= comment.span.end <= len(text)
