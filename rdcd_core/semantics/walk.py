"""Fast walks over expressions and code (ast.walk is generic and slow for the hot paths)."""

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



def code_nodes(node: ast.Stmt | ast.Arg) -> Iterator[ast.Stmt | ast.Arg]:
    """``node`` and every statement and expression below it, blocks entered, in the order of
    ``ast.walk`` (which also gives the names and modifiers)."""
    stack: list[ast.Stmt | ast.Arg] = [node]
    while stack:
        current = stack.pop()
        yield current
        if isinstance(current, ast.Block):
            stack.extend(reversed(current.statements))
        elif isinstance(current, ast.CallStmt):
            stack.append(current.call)
        elif isinstance(current, ast.IfStmt):
            if current.else_body is not None:
                stack.append(current.else_body)
            stack.append(current.then_body)
            stack.append(current.condition)
        elif isinstance(current, ast.SelfCall | ast.FunctionCall | ast.GlobalCall):
            stack.extend(reversed(current.args))
        elif isinstance(current, ast.Binary):
            stack.append(current.right)
            stack.append(current.left)
        elif isinstance(current, ast.Unary | ast.Paren):
            stack.append(current.operand if isinstance(current, ast.Unary) else current.expr)
