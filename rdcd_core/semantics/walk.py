"""Fast walks over expressions and code (ast.walk is generic and slow for the hot paths)."""

from __future__ import annotations

from collections.abc import Iterator

from rdcd_core.syntax import ast

#: the call nodes (their arguments are their children)
CALLS = (ast.SelfCall, ast.FunctionCall, ast.GlobalCall)


def expr_nodes(expr: ast.Arg) -> Iterator[ast.Arg]:
    """``expr`` and every expression below it (blocks are not entered), pre-order."""
    stack: list[ast.Arg] = [expr]
    pop, push = stack.pop, stack.append
    while stack:
        node = pop()
        yield node
        kind = type(node)  # node classes have no subclasses: exact types are the fast test
        if kind is ast.Binary:
            push(node.right)
            push(node.left)
        elif kind is ast.Unary:
            push(node.operand)
        elif kind is ast.Paren:
            push(node.expr)
        elif kind in CALLS:
            stack.extend(reversed([a for a in node.args if type(a) is not ast.Block]))
        elif kind is ast.NeighbourValues and node.where is not None:
            push(node.where)


def code_nodes(node: ast.Stmt | ast.Arg) -> Iterator[ast.Stmt | ast.Arg]:
    """``node`` and every statement and expression below it, blocks entered, in the order of
    ``ast.walk`` (which also gives the names and modifiers)."""
    stack: list[ast.Stmt | ast.Arg] = [node]
    pop, push = stack.pop, stack.append
    while stack:
        current = pop()
        yield current
        kind = type(current)
        if kind is ast.Binary:
            push(current.right)
            push(current.left)
        elif kind in CALLS:
            stack.extend(reversed(current.args))
        elif kind is ast.IfStmt:
            if current.else_body is not None:
                push(current.else_body)
            push(current.then_body)
            push(current.condition)
        elif kind is ast.CallStmt:
            push(current.call)
        elif kind is ast.Block:
            stack.extend(reversed(current.statements))
        elif kind is ast.Unary:
            push(current.operand)
        elif kind is ast.Paren:
            push(current.expr)
        elif kind is ast.AssignStmt:
            push(current.value)
        elif kind is ast.NeighbourValues and current.where is not None:
            push(current.where)
