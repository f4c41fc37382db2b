"""Role conflicts (docs/language.md): two deployed roles whose invariants can both hold on one module.

Decided by evaluating the invariants over a bounded space of abstract module states
(``statespace``), for each neighbour assignment that matters ("every attached neighbour plays R").
Roles whose invariants use anything else are left out: the analysis cannot decide them.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product

from rdcd_core import diagnostics as diag
from rdcd_core.operators import BINARY, UNARY
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.model import RoleSymbol
from rdcd_core.semantics.statespace import StateSpace, Values
from rdcd_core.semantics.walk import expr_nodes
from rdcd_core.syntax import ast
from rdcd_core.types import INT8_MAX, INT8_MIN, PREDEFINED_VALUES, Type

_MAX_PAIRS = 4096  # bound on the size of one binary operation's value table
_MAX_REPS = 7
_MAX_PAIR_CHECKS = 2000  # bound on detailed pair checks (real programs have at most 14 roles)


class _Undecidable(Exception):
    pass


_UNKNOWN = object()  # not in the cache yet


class _Evaluator:
    def __init__(self, ctx: Context, space: StateSpace) -> None:
        self.ctx = ctx
        self.space = space
        self.cache: dict[tuple[str, tuple[bool, ...]], int | None] = {}
        self.sizes: dict[int, Values] = {}

    def states(self, role: RoleSymbol, refs: list[str], played: frozenset[str]) -> int | None:
        """States where every invariant of ``role`` holds, neighbours playing ``played``."""
        signature = tuple([r in played for r in refs]) if refs else ()
        key = (role.name, signature)
        found = self.cache.get(key, _UNKNOWN)
        if found is _UNKNOWN:
            matched = {r for r, hit in zip(refs, signature, strict=True) if hit}
            try:
                found = self.space.full
                for invariant in role.invariants:
                    found &= self._eval(role, invariant.decl.expr, matched).get(1, 0)
                    if not found:
                        break
            except _Undecidable:
                found = None
            self.cache[key] = found
        return found

    def _eval(self, role: RoleSymbol, expr: ast.Expr, matched: set[str]) -> Values:
        full = self.space.full
        if isinstance(expr, ast.IntLit):
            return {expr.value: full}
        if isinstance(expr, ast.Paren):
            return self._eval(role, expr.expr, matched)
        if isinstance(expr, ast.NameRef):
            return {_constant(role, expr.name.text): full}
        if isinstance(expr, ast.Unary):
            inner = self._eval(role, expr.operand, matched)
            operator = UNARY.get(expr.op)
            if operator is None:
                raise _Undecidable
            return _map(inner, operator.apply)
        if isinstance(expr, ast.Binary):
            left = self._eval(role, expr.left, matched)
            right = self._eval(role, expr.right, matched)
            return _combine(expr.op, left, right)
        if isinstance(expr, ast.SelfCall):
            return self._self_call(role, expr, matched)
        if isinstance(expr, ast.FunctionCall):
            return self._function(role, expr, matched)
        raise _Undecidable

    def _self_call(self, role: RoleSymbol, call: ast.SelfCall, matched: set[str]) -> Values:
        name = call.name.text
        if name == "center_position" and not call.args:
            return self.space.axis()
        if name == "total_connected" and not call.args:
            return self.space.total_connected()
        if name in ("x", "y", "z") and not call.args:
            return self.space.coordinate(name)
        if name == "connected" and len(call.args) == 1:
            return self.space.connected(self._single(role, call.args[0], matched))
        raise _Undecidable

    def _function(self, role: RoleSymbol, call: ast.FunctionCall, matched: set[str]) -> Values:
        name = call.name.text
        if name == "sizeof" and len(call.args) == 1 and not isinstance(call.args[0], ast.Block):
            values = self._eval(role, call.args[0], matched)
            key = id(values)
            if self.space.is_cached(values):  # the id of a cached table is stable
                found = self.sizes.get(key)
                if found is None:
                    found = self.sizes[key] = _map(values, int.bit_count)
                return found
            return _map(values, int.bit_count)
        if name == "connected_role" and len(call.args) == 2:
            target = call.args[1]
            if not isinstance(target, ast.NameRef):
                raise _Undecidable
            if target.name.text not in matched:
                return {0: self.space.full}
            return self.space.connected(self._single(role, call.args[0], matched))
        raise _Undecidable

    def _single(self, role: RoleSymbol, arg: ast.Arg, matched: set[str]) -> int:
        if isinstance(arg, ast.Block):
            raise _Undecidable
        values = self._eval(role, arg, matched)
        if len(values) != 1:
            raise _Undecidable
        return next(iter(values))


def _constant(role: RoleSymbol, name: str) -> int:
    symbol = role.constants.get(name)
    if symbol is not None:
        if symbol.value is None:
            raise _Undecidable
        return symbol.value.value
    predefined = PREDEFINED_VALUES.get(name)
    if predefined is None:
        raise _Undecidable
    return predefined.code


def _map(values: Values, function) -> Values:  # type: ignore[no-untyped-def]
    out: Values = {}
    for value, states in values.items():
        result = function(value)
        out[result] = out.get(result, 0) | states
    return out


def _combine(op: str, left: Values, right: Values) -> Values:
    """``left op right`` as the VM computes it (8-bit wrapping arithmetic), state by state."""
    operator = BINARY.get(op)
    if operator is None or len(left) * len(right) > _MAX_PAIRS:
        raise _Undecidable
    function = operator.apply
    out: Values = {}
    for a, states_a in left.items():
        for b, states_b in right.items():
            states = states_a & states_b
            if states:
                result = function(a, b)
                out[result] = out.get(result, 0) | states
    return out


# ----------------------------------------------------------------------------- the analysis


def check_conflicts(ctx: Context, seen: dict[str, ast.Name]) -> None:
    limits = {codes.TOO_MANY_ROLE_IDS, codes.TOO_MANY_COMMANDS}  # the meaning is still clear
    if any(d.severity is diag.Severity.ERROR and d.code not in limits
           for d in ctx.model.diagnostics):
        return
    deployed = [ctx.model.roles[name] for name in ctx.model.deployment]
    shapes: dict[int, _Shape] = {}
    space = StateSpace(_coordinate_reps(deployed, shapes))
    evaluator = _Evaluator(ctx, space)
    refs = {role.name: _refs(ctx, role) for role in deployed}
    played: dict[str, frozenset[str]] = {}
    groups: dict[int, list[RoleSymbol]] = {}
    budget = _MAX_PAIR_CHECKS
    for role in deployed:
        projection = _projection(ctx, evaluator, role, refs[role.name])
        if projection is None:
            continue
        if not projection:
            _report_never(ctx, seen, role, refs[role.name], shapes)
            continue
        found = None
        for key, members in groups.items():
            if not key & projection:
                continue
            for other in members:
                budget -= 1
                found = _conflict(ctx, evaluator, other, role, refs, played) if budget >= 0 else None
                if found is not None or budget < 0:
                    break
            if found is not None or budget < 0:
                break
        groups.setdefault(projection, []).append(role)
        if found is not None:
            _report(ctx, seen, space, role, found, shapes)


def _refs(ctx: Context, role: RoleSymbol) -> list[str]:
    from rdcd_core.semantics.deployment import observed_roles

    return sorted({name for name, _ in observed_roles(ctx, role.name)})


def _played(ctx: Context, name: str, cache: dict[str, frozenset[str]]) -> frozenset[str]:
    """The roles a neighbour plays when it plays ``name`` (a mixin: applied to its base)."""
    found = cache.get(name)
    if found is None:
        symbol = ctx.model.roles[name]
        if symbol.is_mixin:
            found = frozenset({name, *ctx.ancestors(symbol.modifies or name)})
        else:
            found = frozenset(ctx.ancestors(name))
        cache[name] = found
    return found


def _projection(ctx: Context, evaluator: _Evaluator, role: RoleSymbol, refs: list[str]) -> int | None:
    """States where the role can hold for some neighbours; None if undecidable."""
    if len(refs) > 4:
        return None
    union = 0
    for signature in product((False, True), repeat=len(refs)):
        played = frozenset(r for r, hit in zip(refs, signature, strict=True) if hit)
        states = evaluator.states(role, refs, played)
        if states is None:
            return None
        union |= states
    return union


def _conflict(ctx: Context, evaluator: _Evaluator, first: RoleSymbol, second: RoleSymbol,
              refs: dict[str, list[str]],
              played_cache: dict[str, frozenset[str]]) -> tuple[RoleSymbol, int, str | None] | None:
    candidates: list[tuple[frozenset[str], str | None]] = [(frozenset(), None)]
    for name in sorted({*refs[first.name], *refs[second.name]}):
        candidates.append((_played(ctx, name, played_cache), name))
    for played, neighbour in candidates:
        a = evaluator.states(first, refs[first.name], played)
        b = evaluator.states(second, refs[second.name], played)
        if a is None or b is None:
            return None
        if a & b:
            return first, a & b, neighbour
    return None


def _report(ctx: Context, seen: dict[str, ast.Name], space: StateSpace, role: RoleSymbol,
            found: tuple[RoleSymbol, int, str | None], shapes: dict[int, _Shape]) -> None:
    other, states, neighbour = found
    axis, connset, coords = space.describe(states)
    used = _features(role, shapes) | _features(other, shapes)
    parts = []
    if "axis" in used:
        parts.append(f"axis {axis}")
    if "connset" in used:
        channels = ", ".join(str(c) for c in range(8) if connset >> c & 1)
        parts.append(f"connectors {{{channels}}} attached" if channels else "no neighbours")
    parts += [f"{c} = {coords[c]}" for c in "xyz" if c in used]
    if neighbour is not None:
        parts.append(f"neighbours playing '{neighbour}'")
    witness = ", ".join(parts) or "any module"
    related = [diag.Related(seen[other.name].span, f"'{other.name}' is deployed here")]
    if other.decl is not None:
        related.append(diag.Related(other.decl.name.span, f"role '{other.name}'"))
    ctx.report(codes.ROLE_CONFLICT, seen[role.name].span,
               f"'{role.name}' and '{other.name}' can both hold on one module (e.g. {witness}); "
               f"such a module takes '{other.name}', the first of the two in the deployment, "
               f"never '{role.name}'; add an invariant that tells them apart if it should take "
               f"'{role.name}'", related=related)


def _report_never(ctx: Context, seen: dict[str, ast.Name], role: RoleSymbol, refs: list[str],
                  shapes: dict[int, _Shape]) -> None:
    """Only where the state space is exact: no neighbour roles, no coordinates."""
    if refs or _features(role, shapes) & {"x", "y", "z"}:
        return
    related = tuple(diag.Related(inv.decl.span, f"invariant of '{inv.owner}'")
                    for inv in role.invariants)
    ctx.report(codes.NEVER_HOLDS, seen[role.name].span,
               f"no module can ever take '{role.name}': its invariants contradict each other "
               "for every axis and set of attached connectors; fix or remove them",
               related=related)


@dataclass(frozen=True, slots=True)
class _Shape:
    """What the analysis reads of one invariant: computed once, as inherited invariants repeat in
    every sub-role."""

    features: frozenset[str]  # of the state: axis, connset, x, y, z
    coordinates: frozenset[str]  # x, y, z
    numbers: frozenset[int]  # the integer literals
    names: tuple[str, ...]  # the bare names (constants, predefined values)


def _shape(expr: ast.Expr, shapes: dict[int, _Shape]) -> _Shape:
    found = shapes.get(id(expr))
    if found is None:
        features: set[str] = set()
        numbers: set[int] = set()
        names: list[str] = []
        for node in expr_nodes(expr):
            if isinstance(node, ast.SelfCall):
                name = node.name.text
                if name == "center_position":
                    features.add("axis")
                elif name in ("x", "y", "z"):
                    features.add(name)
                else:
                    features.add("connset")
            elif isinstance(node, ast.FunctionCall):
                features.add("connset")
            elif isinstance(node, ast.IntLit):
                numbers.add(node.value)
            elif isinstance(node, ast.NameRef):
                names.append(node.name.text)
        found = shapes[id(expr)] = _Shape(frozenset(features), frozenset(features & {"x", "y", "z"}),
                                          frozenset(numbers), tuple(names))
    return found


def _features(role: RoleSymbol, shapes: dict[int, _Shape]) -> set[str]:
    used: set[str] = set()
    for invariant in role.invariants:
        used |= _shape(invariant.decl.expr, shapes).features
    return used


def _coordinate_reps(roles: list[RoleSymbol], shapes: dict[int, _Shape]) -> dict[str, list[int]]:
    """Representative values of x, y, z: around every integer the invariants compare them with."""
    wanted: dict[str, set[int]] = {}
    for role in roles:
        for invariant in role.invariants:
            shape = _shape(invariant.decl.expr, shapes)
            names = shape.coordinates
            if not names:
                continue
            numbers = set(shape.numbers)
            for name in shape.names:
                symbol = role.constants.get(name)
                if symbol is not None and symbol.value is not None and symbol.value.type is Type.INT:
                    numbers.add(symbol.value.value)
            for name in names:
                values = wanted.setdefault(name, {0})
                for number in numbers:
                    values.update((number - 1, number, number + 1, -number - 1, -number, -number + 1))
    # a coordinate is a signed byte on the VM: 128 or -129 is no module's position
    return {name: sorted((v for v in values if INT8_MIN <= v <= INT8_MAX), key=abs)[:_MAX_REPS]
            for name, values in wanted.items()}
