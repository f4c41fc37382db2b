"""A fast walk over expression trees (ast.walk is generic and slow for the hot paths)."""

from __future__ import annotations

from collections.abc import Iterator

from rdcd_core.syntax import ast


def expr_nodes(expr: ast.Arg) -> Iterator[ast.Arg]:
    """``expr`` and every expression below it (blocks are not entered), pre-order."""
    stack: list[ast.Arg] = [expr]
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, ast.Binary):
            stack.append(node.right)
            stack.append(node.left)
        elif isinstance(node, ast.Unary | ast.Paren):
            stack.append(node.operand if isinstance(node, ast.Unary) else node.expr)
        elif isinstance(node, ast.SelfCall | ast.FunctionCall | ast.GlobalCall):
            stack.extend(reversed([a for a in node.args if not isinstance(a, ast.Block)]))

