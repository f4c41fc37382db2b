"""Helpers shared by the syntax tests."""

from __future__ import annotations

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


def check_spans(text: str, program: ast.Program) -> None:
    """Every span lies in the text and inside its parent's span."""
    stack = [(program, program.span)]
    while stack:
        node, parent = stack.pop()
        span = node.span
        assert 0 <= span.start <= span.end <= len(text), (node, len(text))
        assert parent.start <= span.start and span.end <= parent.end, (node, parent)
        stack.extend((child, span) for child in ast.children(node))
    for comment in program.comments:
        assert 0 <= comment.span.start <= comment.span.end <= len(text)
