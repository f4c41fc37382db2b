"""First role wins (docs/language.md, "Invariants and discovery order"): a module takes the first
deployed role whose invariants hold. Sibling roles discovered by one fragment test in deployment
order; across fragments, which arrive and run in deployment order, a later fragment must not take
its role on a module that an earlier one gave a role. It starts with ``HAS_ROLE 0`` (3 bytes: "no
role yet") — but only when an earlier deployed role can hold on a module where one of its roles
holds: where no module can satisfy both (decided over the local states, below), no test is needed
and no byte is spent. A guarded fragment also waits (SLEEP) when such an earlier fragment waits,
so that it runs after it on every module.

Whether two roles can both hold is decided by over-approximating each role over the local states
(axis x connected set): a local invariant by its exact mask, an invariant that also reads
``connected_role(d, R)`` by trying every subset of the connectors facing ``d`` as its value (the
neighbours there may play R or not), any other invariant as "may hold anywhere".
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.fold import _eval_query, fold
from rdcd_core.compiler.geometry import ALL_STATES, LOCAL_STATES, facing
from rdcd_core.operators import BINARY, UNARY
from rdcd_core.syntax import ast

_MAX_TERMS = 2  # connected_role terms in one invariant tried exhaustively
_MAX_TRIALS = 20_000  # evaluations for one invariant; beyond that it "may hold anywhere" (a guard)


class _Unknown(Exception):
    pass


@dataclass(frozen=True, slots=True)
class Guard:
    guarded: bool  # an earlier deployed role can hold where a role of the fragment holds
    waits: bool  # the fragment of such a role waits (SLEEP): this one must wait too


def local_part(ctx: Context) -> int:
    """Local states in which the role's local invariants hold (the others ignored): a superset."""
    from rdcd_core.compiler.discovery import invariants, role_mask

    key = ("local_part", ctx.role)
    if key not in ctx.cache:
        ctx.cache[key] = role_mask(invariants(ctx), ctx, local_only=True)
    return ctx.cache[key]  # type: ignore[return-value]


def may_hold(ctx: Context) -> int:
    """Local states in which the role's invariants can all hold (a superset: never misses one)."""
    from rdcd_core.compiler.discovery import state_mask

    key = ("may_hold", ctx.role)
    if key not in ctx.cache:
        mask = ALL_STATES
        for inv in ctx.model.roles[ctx.role].invariants:
            expr = inv.decl.expr
            part = state_mask(expr, ctx)
            mask &= part if part is not None else _with_neighbour_roles(expr, ctx)
            if not mask:
                break
        ctx.cache[key] = mask
    return ctx.cache[key]  # type: ignore[return-value]


def earlier_overlapping(ctx: Context, earlier: list[Context]) -> list[Context]:
    """The roles of ``earlier`` (deployed before ``ctx.role``) that can hold where it holds."""
    local = local_part(ctx)  # cheap first: most pairs are told apart by their local invariants
    return [other for other in earlier if local_part(other) & local and may_hold(other) & may_hold(ctx)]


def _with_neighbour_roles(expr: ast.Node, ctx: Context) -> int:
    terms = [node for node in ast.walk(expr)
             if isinstance(node, ast.FunctionCall) and node.name.text == "connected_role"]
    if not terms or len(terms) > _MAX_TERMS:
        return ALL_STATES
    directions = []
    for term in terms:
        direction = fold(term.args[0], ctx) if len(term.args) == 2 else None
        if direction is None:
            return ALL_STATES
        directions.append(direction.value)
    mask, trials = 0, 0
    try:
        for index, state in enumerate(LOCAL_STATES):
            axis, connected = state
            choices = [_subsets(connected & facing(axis, d)) for d in directions]
            for values in product(*choices):
                trials += 1
                if trials > _MAX_TRIALS:
                    return ALL_STATES
                assigned = {id(term): value for term, value in zip(terms, values, strict=True)}
                if _value(expr, ctx, state, assigned):
                    mask |= 1 << index
                    break
    except _Unknown:
        return ALL_STATES
    return mask


def _subsets(bits: int) -> list[int]:
    found, sub = [], bits
    while True:
        found.append(sub)
        if not sub:
            return found
        sub = (sub - 1) & bits


def _value(expr: ast.Node, ctx: Context, state: tuple[int, int], assigned: dict[int, int]) -> int:
    expr = ast.unparen(expr)
    if id(expr) in assigned:
        return assigned[id(expr)]
    if isinstance(expr, ast.Unary):
        return UNARY[expr.op].apply(_value(expr.operand, ctx, state, assigned))
    if isinstance(expr, ast.Binary):
        return BINARY[expr.op].apply(_value(expr.left, ctx, state, assigned),
                                     _value(expr.right, ctx, state, assigned))
    if isinstance(expr, ast.FunctionCall) and expr.name.text == "sizeof" and len(expr.args) == 1:
        return bin(_value(expr.args[0], ctx, state, assigned) & 0xFF).count("1")
    folded = fold(expr, ctx)
    if folded is not None:
        return folded.value
    if isinstance(expr, ast.SelfCall):
        found = _eval_query(expr, ctx, state)
        if found is not None:
            return found.value
    raise _Unknown
