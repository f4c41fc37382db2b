"""Target-driven lowerings that need the local state space: which axes and connector sets may
reach the code being generated (``Context.states``), and the forms of ``CONNECTED_DIR_SIZEOF``
that are exact on a target whose instruction counts wrongly or halts for some axis and direction
(``vm.isa.targets``: ``dir_sizeof_pairs``, ``Quirks.connected_dir_sizeof_popcount_of_count``).

The original firmware's CONNECTED_DIR_SIZEOF pushes the number of bits set *in the count*
(0, 1, 2, 3, 4 connections read 0, 1, 1, 2, 1); this project's VM pushes the count itself. Code
for the original target must decide alike on both profiles (tests/vm/test_original_target_property.py),
so a comparison ``sizeof(self.connected(d)) op k`` is compiled as a test of the reading only when
the test is exact under both readings, over the counts that can occur in the reachable states; no
such test exists when a count that makes it true and one that makes it false can push the same
value on either profile (3 reads 2 on the firmware, 2 reads 2 here: ``== 3`` beside a possible 2).
"""

from __future__ import annotations

from collections.abc import Callable

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.geometry import DIRECTION_NAMES, LOCAL_STATES, facing
from rdcd_core.compiler.ir import Ins, Item, Label
from rdcd_core.operators import BINARY
from rdcd_core.semantics.model import Model
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.types import PREDEFINED_VALUES, Type

AXIS_NAMES = {v.code: name for name, v in PREDEFINED_VALUES.items() if v.type is Type.AXIS}


def reachable(ctx: Context) -> list[tuple[int, int]]:
    """(axis, connected set) of every local state the current code may run in."""
    if ctx.states is None:
        return list(LOCAL_STATES)
    key = ("reachable", ctx.states)
    if key not in ctx.cache:
        mask = ctx.states
        ctx.cache[key] = [state for index, state in enumerate(LOCAL_STATES) if mask >> index & 1]
    return ctx.cache[key]  # type: ignore[return-value]


def axis_states(model: Model, role: str, local_mask: int | None) -> int | None:
    """The states of every axis that ``local_mask`` (the role's local invariants) allows: what a
    module playing the role may be in later (its axis cannot change, its connections can)."""
    if local_mask is None:
        return None
    axes = {axis for index, (axis, _) in enumerate(LOCAL_STATES) if local_mask >> index & 1}
    return sum(1 << index for index, (axis, _) in enumerate(LOCAL_STATES) if axis in axes)


def dir_sizeof_runs(ctx: Context, direction: int, span: Span) -> bool:
    """Whether CONNECTED_DIR_SIZEOF ``direction`` runs on the target on every reachable axis;
    reports the first axis where it would halt the module."""
    for axis in sorted({axis for axis, _ in reachable(ctx)}):
        if not ctx.target.dir_sizeof_runs(axis, direction):
            ctx.cannot(span, f"the connectors facing {DIRECTION_NAMES.get(direction, direction)} of a "
                             f"module with axis {AXIS_NAMES.get(axis, axis)} cannot be counted: the "
                             f"{ctx.target.name} target's CONNECTED_DIR_SIZEOF halts the module there; "
                             "test the module's axis before (self.center_position == ...)")
            return False
    return True


def reading(ctx: Context, count: int) -> int:
    """What the target's CONNECTED_DIR_SIZEOF pushes for ``count`` connections."""
    return bin(count).count("1") if ctx.target.quirks.connected_dir_sizeof_popcount_of_count else count


def readings(ctx: Context, count: int) -> set[int]:
    """What CONNECTED_DIR_SIZEOF may push for ``count`` connections when this target's code runs:
    the target's reading and, for a target that miscounts, the right count (the default profile)."""
    return {reading(ctx, count), count}


def counts(ctx: Context, direction: int) -> set[int]:
    return {bin(connected & facing(axis, direction)).count("1") for axis, connected in reachable(ctx)}


def dir_count_is_exact(ctx: Context, direction: int) -> bool:
    """Whether the target's CONNECTED_DIR_SIZEOF reads every reachable count as itself."""
    return all(reading(ctx, n) == n for n in counts(ctx, direction))


def _reading_tests(span: Span) -> list[tuple[list[Ins], list[Ins], Callable[[int], bool]]]:
    """The tests of the reading r, cheapest first (r > 1 before the others keeps the bytes the
    lowering chose before): (instructions before CONNECTED_DIR_SIZEOF, after it, the predicate)."""
    tests: list[tuple[list[Ins], list[Ins], Callable[[int], bool]]] = [
        ([], [], lambda r: r != 0), ([], [Ins("EQUALS_1", (), span)], lambda r: r == 1)]
    for j in (1, 0, 2, 3):
        tests.append(([], [Ins("PUSH", (j,), span), Ins("GREATER", (), span)], lambda r, j=j: r > j))
    for j in (1, 2, 3, 4):
        tests.append(([Ins("PUSH", (j,), span)], [Ins("GREATER", (), span)], lambda r, j=j: j > r))
    return tests


def dir_count_jump(direction: int, op: str, k: int, target: Label, when: bool, ctx: Context,
                   out: list[Item], span: Span) -> None:
    """Jump to ``target`` when ``(sizeof(self.connected(direction)) op k) == when``, through a test
    of CONNECTED_DIR_SIZEOF's reading that is exact on every profile (the module docstring)."""
    if not dir_sizeof_runs(ctx, direction, span):
        return
    possible = counts(ctx, direction)
    true = {r for n in possible if BINARY[op].apply(n, k) for r in readings(ctx, n)}
    false = {r for n in possible if not BINARY[op].apply(n, k) for r in readings(ctx, n)}
    name = DIRECTION_NAMES.get(direction, direction)
    if true & false:
        ctx.cannot(span, f"sizeof(self.connected({name})) {op} {k} cannot be tested: the "
                         f"{ctx.target.name} target's CONNECTED_DIR_SIZEOF reads 1, 2 and 4 "
                         "connections alike and 3 as 2, where the default VM reads each count as "
                         "itself, and the code must decide alike on both; compare the count with 0 "
                         "instead")
        return
    if not true or not false:  # the same on every reachable state
        if bool(true) == when:
            out.append(Ins("GOTO", (target,), span))
        return
    for before, after, holds in _reading_tests(span):
        if all(holds(r) for r in true) and not any(holds(r) for r in false):
            jump = "IF_TRUE_GOTO" if when else "IF_FALSE_GOTO"
        elif all(holds(r) for r in false) and not any(holds(r) for r in true):
            jump = "IF_FALSE_GOTO" if when else "IF_TRUE_GOTO"
        else:
            continue
        out.extend(before)
        out.append(Ins("CONNECTED_DIR_SIZEOF", (direction,), span))
        out.extend(after)
        out.append(Ins(jump, (target,), span))
        return
    ctx.cannot(span, f"sizeof(self.connected({name})) {op} {k} cannot be tested with the "
                     f"{ctx.target.name} target's instructions; compare the count with 0 instead")


def connected_direction(expr: ast.Node, ctx: Context) -> int | None:
    """The direction d of ``sizeof(self.connected(d))`` (d a constant), else None."""
    from rdcd_core.compiler.fold import fold

    expr = ast.unparen(expr)
    if not (isinstance(expr, ast.FunctionCall) and expr.name.text == "sizeof" and len(expr.args) == 1):
        return None
    inner = ast.unparen(expr.args[0])
    if not (isinstance(inner, ast.SelfCall) and inner.name.text == "connected" and len(inner.args) == 1):
        return None
    direction = fold(inner.args[0], ctx)
    return None if direction is None else direction.value
