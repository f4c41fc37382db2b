"""Connector and joint actions (``self.connect(c)``, ``self.disconnect(c)``,
``self.turnQuarters(n)``) change the robot, so each must run exactly once where it is written:
as a statement, as the condition of an ``if`` (possibly negated), or as the value of a state
assignment. Anywhere else — an invariant (role discovery evaluates invariants again and again),
an operand of a comparison (compiled by evaluating operands twice), an argument of a plain method
(inlined where each parameter is read) — is E320."""

from __future__ import annotations

from rdcd_core.module_api import ACTIONS
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context
from rdcd_core.syntax import ast


def _is_action(node: object) -> bool:
    return isinstance(node, ast.SelfCall) and node.name.text in ACTIONS


def _strip(expr: object) -> object:
    expr = ast.unparen(expr)  # type: ignore[arg-type]
    while isinstance(expr, ast.Unary) and expr.op == "!":
        expr = ast.unparen(expr.operand)
    return expr


def check_positions(ctx: Context, program: ast.Program) -> None:
    allowed: set[int] = set()
    actions = []
    for node in ast.walk(program):
        if isinstance(node, ast.CallStmt):
            allowed.add(id(node.call))
        elif isinstance(node, ast.IfStmt):
            allowed.add(id(_strip(node.condition)))
        elif isinstance(node, ast.AssignStmt):
            allowed.add(id(ast.unparen(node.value)))  # type: ignore[arg-type]
        if _is_action(node):
            actions.append(node)
    for node in actions:
        if id(node) not in allowed:
            ctx.report(codes.ACTION_IN_EXPRESSION, node.span,
                       f"'self.{node.name.text}' changes the robot and must run exactly once: use it as a "
                       "statement, as the condition of an if (e.g. if (!self.connect(0)) …), or assign "
                       "it to a state; never in an invariant or inside another expression")
