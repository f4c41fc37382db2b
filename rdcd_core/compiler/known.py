"""The values a command's argument can have, when the program only ever sends it constants.

For a target whose joint instructions take their value only as an operand (``--target original``:
the firmware has no ``TURN_TO_STACK``), an argument computed from a command's parameter can still
be compiled when the program sends that command a small, known set of values: one constant
instruction per value, chosen by comparing the argument (a *table*). Every call site
``Role.name(arg)`` of the whole program must fold to a constant in the role whose code holds it;
one that does not (a state, another command's argument) means the set is unknown (None), and the
compiler reports E605 as before. Nothing else sends a user command: the set is exact.
"""

from __future__ import annotations

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.fold import fold
from rdcd_core.semantics.model import RoleKind
from rdcd_core.syntax import ast

MAX_TABLE = 4  # values a table tests at most: each costs about 11 bytes


def sent_values(ctx: Context, command: str) -> frozenset[int] | None:
    """Every value some code of the program sends as command ``command``'s argument (None when
    one of them is not a constant). Memoised per compilation."""
    key = ("sent", command)
    if key not in ctx.cache:
        ctx.cache[key] = _sent_values(ctx, command)
    return ctx.cache[key]  # type: ignore[return-value]


def _sent_values(ctx: Context, command: str) -> frozenset[int] | None:
    values: set[int] = set()
    for role in ctx.model.roles.values():
        if role.kind is not RoleKind.CONCRETE:  # abstract roles' code is copied into their sub-roles
            if any(_calls(m.decl.body, command) for m in role.methods.values() if m.decl.body is not None):
                if role.kind is RoleKind.MIXIN:
                    return None  # a mixin's code runs in roles of its own: not folded here
            continue
        caller = Context(ctx.model, ctx.table, role.name, target=ctx.target)
        for method in role.methods.values():
            if method.decl.body is None:
                continue
            for call in _calls(method.decl.body, command):
                if not call.args or isinstance(call.args[0], ast.Block):
                    values.add(0)  # sent without an argument: 0
                    continue
                folded = fold(call.args[0], caller)
                if folded is None:
                    return None
                values.add(folded.value)
    return frozenset(values)


def _calls(body: ast.Node, command: str) -> list[ast.GlobalCall]:
    return [node for node in ast.walk(body) if isinstance(node, ast.GlobalCall) and node.name.text == command]


def literal(value: int, span: object) -> ast.Node:
    """``value`` as an expression (a negative number is the unary minus of a literal)."""
    if value >= 0:
        return ast.IntLit(value, span)  # type: ignore[arg-type]
    return ast.Unary("-", ast.IntLit(-value, span), span)  # type: ignore[arg-type]


def known_values(arg: ast.Node, ctx: Context) -> list[tuple[int, int]] | None:
    """(parameter value, value of ``arg``) for each value the program sends the command whose body
    is being compiled, sorted by the parameter value: when ``arg`` folds for each and they are at
    most MAX_TABLE; otherwise None."""
    if ctx.argument is None or ctx.command is None:
        return None
    sent = sent_values(ctx, ctx.command)
    if not sent or len(sent) > MAX_TABLE:
        return None
    found: list[tuple[int, int]] = []
    saved = ctx.argument, ctx.bindings
    try:
        for value in sorted(sent):
            ctx.argument = None  # the parameter stands for this value, as a plain method's argument
            ctx.bindings = {**saved[1], saved[0]: (literal(value, arg.span), {})}  # type: ignore[attr-defined]
            folded = fold(arg, ctx)
            if folded is None:
                return None
            found.append((value, folded.value))
    finally:
        ctx.argument, ctx.bindings = saved
    return found
