"""Which module holds which role in a lattice structure, found the way the DCD-VM finds it: a
module takes the first deployed role whose invariants (inherited ones included) hold
(docs/language.md "Invariants and discovery order").

The checker evaluates invariants on the structure itself: ``self.center_position``,
``self.total_connected()``, ``self.connected(d)``, ``self.x()``..``z()``, ``isConnected``,
``isAligned``, ``sizeof``, ``connected_role`` (from the roles found so far, repeated until they
settle), constants and states at their initial values. Anything else (the neighbours' published
values) is *unknown*: ``None``, and a role whose invariants are unknown may or may not hold.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from rdcd_core.semantics.model import Model
from rdcd_core.syntax import ast
from rdcd_core.types import PREDEFINED_VALUES
from vm import navigation
from vm.isa.opcodes import divided, remainder, saturated

if TYPE_CHECKING:
    from vm.lattice.structure import Structure

Unknown = None
_MAX_ROUNDS = 8  # connected_role: rounds until the roles settle (a chain settles one hop a round)


class _Env:
    """A structure as its modules know it: links as they are now; cells, axes and connector
    directions as each module learned them (docs/language.md "Coordinates after a move": a module
    that keeps a connection keeps its coordinates and orientation; one that was alone takes the
    actual ones when attached again)."""

    def __init__(self, model: Model, structure: Structure, roles: dict[int, str | None],
                 learned: dict[int, Any] | None = None) -> None:
        self.model = model
        self.structure = structure
        self.roles = roles
        self.learned = learned if learned is not None else {}

    def spec(self, mid: int) -> Any:
        return self.learned.get(mid) or self.structure.modules[mid]

    def connset(self, mid: int, direction: tuple[int, int, int] | None) -> int:
        """Bit v: virtual channel v is latched (and faces ``direction`` if given)."""
        from vm.lattice.structure import directions

        spec = self.spec(mid)
        faces = directions(spec)
        offsets = [navigation.offset(spec.axis, v) for v in range(8)]
        mask = 0
        for physical in self.structure.neighbours(mid):
            off = faces[physical]
            if direction is not None and sum(a * b for a, b in zip(off, direction, strict=True)) <= 0:
                continue
            if off in offsets:
                mask |= 1 << offsets.index(off)
        return mask

    def across(self, mid: int, channel: int) -> int | None:
        """The neighbour latched on virtual channel ``channel`` (as the module knows its channels)."""
        from vm.lattice.structure import directions

        spec = self.spec(mid)
        faces = directions(spec)
        off = navigation.offset(spec.axis, channel)
        for physical, (other, _) in self.structure.neighbours(mid).items():
            if faces[physical] == off:
                return other
        return None


def evaluate(expr: Any, model: Model, role: str | None, env: _Env, mid: int) -> Any:
    """The value of ``expr`` on module ``mid`` playing ``role`` (for its constants and states):
    an int (booleans 0/1), or None when it cannot be known before the run."""
    e = ast.unparen(expr)
    if isinstance(e, ast.IntLit):
        return e.value
    if isinstance(e, ast.NameRef):
        return _name(e.name.text, model, role)
    if isinstance(e, ast.Unary):
        v = evaluate(e.operand, model, role, env, mid)
        if v is None:
            return None
        return -v if e.op == "-" else int(not v)
    if isinstance(e, ast.Binary):
        return _binary(e, model, role, env, mid)
    if isinstance(e, ast.SelfCall):
        return _self_call(e, model, role, env, mid)
    if isinstance(e, ast.FunctionCall):
        return _function(e, model, role, env, mid)
    return None


def _name(name: str, model: Model, role: str | None) -> Any:
    symbol = model.roles.get(role) if role else None
    if symbol is not None:
        constant = symbol.constants.get(name)
        if constant is not None:
            return constant.value.value if constant.value is not None else None
        state = symbol.states.get(name)
        if state is not None:
            return state.initial
    state = model.states.get(name)
    if state is not None:
        return state.initial
    value = PREDEFINED_VALUES.get(name)
    if value is not None:
        return value.code
    if name in model.roles:
        return name
    return None


def _binary(e: ast.Binary, model: Model, role: str | None, env: _Env, mid: int) -> Any:
    left = evaluate(e.left, model, role, env, mid)
    if e.op == "&&" and left == 0:
        return 0
    if e.op == "||" and left not in (0, None):
        return 1
    right = evaluate(e.right, model, role, env, mid)
    if e.op == "&&":
        return None if left is None or right is None else int(bool(right))
    if e.op == "||":
        if right not in (0, None):
            return 1
        return None if left is None or right is None else 0
    if left is None or right is None:
        return None
    ops = {"==": lambda a, b: int(a == b), "!=": lambda a, b: int(a != b),
           "<": lambda a, b: int(a < b), ">": lambda a, b: int(a > b),
           "<=": lambda a, b: int(a <= b), ">=": lambda a, b: int(a >= b),
           "+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: saturated(a * b),
           "/": lambda a, b: divided(a, b) if b else None,
           "%": lambda a, b: remainder(a, b) if b else None}  # as the VM computes them
    op = ops.get(e.op)
    try:
        return op(left, right) if op is not None else None
    except TypeError:  # a role name against a number: not a value the checker knows
        return None


def _self_call(e: ast.SelfCall, model: Model, role: str | None, env: _Env, mid: int) -> Any:
    spec = env.spec(mid)
    name = e.name.text
    if name == "center_position":
        return spec.axis
    if name in ("x", "y", "z"):
        return spec.position["xyz".index(name)]
    if name == "total_connected":
        return env.connset(mid, None)
    if name == "connected" and len(e.args) == 1:
        d = evaluate(e.args[0], model, role, env, mid)
        vector = navigation.DIRECTION_VECTORS.get(d) if isinstance(d, int) else None
        return env.connset(mid, vector) if vector is not None else None
    if name in ("isConnected", "isAligned") and len(e.args) == 1:
        c = evaluate(e.args[0], model, role, env, mid)
        if not isinstance(c, int) or not 0 <= c < 8:
            return None
        if name == "isConnected":
            return int(c in env.structure.neighbours(mid))
        return int(env.structure.facing(mid, c) is not None)
    return None


def _function(e: ast.FunctionCall, model: Model, role: str | None, env: _Env, mid: int) -> Any:
    name = e.name.text
    if name == "sizeof" and len(e.args) == 1:
        s = evaluate(e.args[0], model, role, env, mid)
        return bin(s).count("1") if isinstance(s, int) else None
    if name == "connected_role" and len(e.args) == 2:
        d = evaluate(e.args[0], model, role, env, mid)
        wanted = ast.unparen(e.args[1])
        if not isinstance(wanted, ast.NameRef) or d not in navigation.DIRECTION_VECTORS:
            return None
        mask = env.connset(mid, navigation.DIRECTION_VECTORS[d])
        out = 0
        for v in range(8):
            if mask >> v & 1:
                other = env.across(mid, v)
                held = env.roles.get(other) if other is not None else None
                if held is not None and model.is_subrole(held, wanted.name.text):
                    out |= 1 << v
        return out
    if name in ("min", "max") and len(e.args) == 2:
        a = evaluate(e.args[0], model, role, env, mid)
        b = evaluate(e.args[1], model, role, env, mid)
        if isinstance(a, int) and isinstance(b, int):
            return min(a, b) if name == "min" else max(a, b)
    return None


def holds(model: Model, role: str, env: _Env, mid: int) -> Any:
    """1 if every invariant of ``role`` holds on ``mid``, 0 if one does not, None if unknown."""
    symbol = model.roles.get(role)
    if symbol is None:
        return 0
    result: Any = 1
    for invariant in symbol.invariants:
        v = evaluate(invariant.decl.expr, model, role, env, mid)
        if v == 0:
            return 0
        if v is None:
            result = None
    return result


def find_roles(model: Model, structure: Structure, learned: dict[int, Any] | None = None
               ) -> tuple[dict[int, str | None], set[int]]:
    """The role of every module (None: none holds), and the modules whose role is uncertain."""
    roles: dict[int, str | None] = {m: None for m in structure.modules}
    uncertain: set[int] = set()
    for _ in range(_MAX_ROUNDS):
        env = _Env(model, structure, dict(roles), learned)
        found: dict[int, str | None] = {}
        uncertain = set()
        for mid in sorted(structure.modules):
            found[mid] = None
            for role in model.deployment:
                v = holds(model, role, env, mid)
                if v is None:
                    uncertain.add(mid)
                    found[mid] = role
                    break
                if v:
                    found[mid] = role
                    break
        if found == roles:
            break
        roles = found
    return roles, uncertain


def entry_frame(structure: Structure) -> dict[int, Any]:
    """Every module's place as the modules learn it: in the entry module's frame (the entry is the
    origin, NORTH_SOUTH, identity mount, wherever it is). Equal to the structure's own places for
    a configuration; not for a structure some steps have left with the entry moved or turned (the
    end of a sequence, where a run backwards starts)."""
    from dataclasses import replace

    from vm.lattice.geometry import placement
    from vm.lattice.motion import compose, orientation_of

    entry = structure.modules[structure.entry]
    turn = placement(entry.axis, entry.mount)
    back = tuple(tuple(turn[j][i] for j in range(3)) for i in range(3))  # the inverse: transposed
    out = {}
    for mid, spec in structure.modules.items():
        d = tuple(a - b for a, b in zip(spec.position, entry.position, strict=True))
        position = tuple(sum(back[i][j] * d[j] for j in range(3)) for i in range(3))
        axis, mount = orientation_of(compose(back, placement(spec.axis, spec.mount)))  # type: ignore[arg-type]
        out[mid] = replace(spec, position=position, axis=axis, mount=mount)
    return out


def vm_frames(learned: dict[int, Any]) -> dict[int, tuple[tuple[int, int, int], int, tuple[int, ...]]]:
    """What each module of ``learned`` (places as the modules know them) holds in the DCD-VM: its
    coordinates, axis and virtual-to-physical map (the mount's map, the north ring turned with
    the joint as it was when the module learned it)."""
    from vm.lattice.structure import directions

    out = {}
    for mid, spec in learned.items():
        faces = directions(spec)
        out[mid] = (tuple(spec.position), spec.axis,
                    tuple(faces.index(navigation.offset(spec.axis, v)) for v in range(8)))
    return out


def environment(model: Model, structure: Structure, roles: dict[int, str | None],
                learned: dict[int, Any] | None = None) -> _Env:
    return _Env(model, structure, roles, learned)
