"""The operations that change a ``Structure``, each checked here and only here (docs/simulator.md
"Structures that change"): latch, unlatch, rotate a part, add a module, remove a module.

Every operation returns a ``Change``: ``ok`` with what happened, or not ``ok`` with a ``cause``
(a word a program or a report can test) and a one-line ``reason``. A run-time impossibility is a
failed ``Change``, never an exception. The ATRON's rules (USSR's ATRON model, JonKjaersgaard/
alt-ussr ``native/include/atron.h`` and ``ATRONController.java``):

- only a male connector (even number) latches or unlatches, onto the female connector (odd) of the
  module on the adjacent cell that faces it (a link that a configuration file made between two
  connectors of one sex is opened from either end);
- a quarter turn of a module's joint carries everything attached to the turning hemisphere; it is
  blocked when the turning part is also held by the other side (a loop through the structure),
  or when a carried module would sweep through an occupied or blocked cell, or below the ground.

Which hemisphere turns (``moving``: 0 north, connectors 0-3; 1 south, 4-7), unless the caller
says: an empty side (nothing to carry); else the side that does not rest on the ground (has no
module at ``ground_z``) when exactly one side does; else the side with fewer modules; else north.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from vm.lattice import motion
from vm.lattice.geometry import placement

if TYPE_CHECKING:
    from vm.lattice.structure import Link, ModuleSpec, Structure

Vec = tuple[int, int, int]

CAUSES = ("no_module", "bad_connector", "female", "not_aligned", "faces_male", "in_use",
          "not_latched", "loop", "collision", "ground", "occupied", "no_contact", "bad_place", "jammed")


@dataclass(frozen=True)
class Change:
    """What an operation did, or why it could not. ``parts``: when the change split a part of
    the structure in two or more, the parts it left (sorted by lowest id); otherwise ()."""

    ok: bool
    op: str  # "latch" | "unlatch" | "rotate" | "add" | "remove"
    module: int
    connector: int | None = None
    quarters: int = 0
    cause: str = ""  # one of CAUSES when not ok
    reason: str = ""  # one line, when not ok
    link: Link | None = None  # latch / unlatch: the link made or opened
    moved: tuple[int, ...] = ()  # rotate: the carried modules (sorted), add: the new module
    moving: int | None = None  # rotate: the hemisphere that turned (0 north, 1 south)
    blocked_by: tuple[Vec, ...] = ()  # rotate: the cells a carried module would hit
    parts: tuple[frozenset[int], ...] = ()

    def describe(self) -> str:
        what = {"latch": f"latch {self.module}.{self.connector}",
                "unlatch": f"unlatch {self.module}.{self.connector}",
                "rotate": f"rotate {self.module} by {self.quarters} quarter(s)",
                "add": f"add {self.module}", "remove": f"remove {self.module}"}[self.op]
        return what + ("" if self.ok else f" failed: {self.reason}")


def _fail(op: str, module: int, cause: str, reason: str, **kw: object) -> Change:
    return Change(False, op, module, cause=cause, reason=reason, **kw)  # type: ignore[arg-type]


def _done(s: Structure, change: Change) -> Change:
    s.version += 1
    for listener in list(s.listeners):
        listener(change)
    return change


def _connector(s: Structure, op: str, module: int, physical: object) -> Change | None:
    if module not in s.modules:
        return _fail(op, module, "no_module", f"no module {module}")
    if not isinstance(physical, int) or not 0 <= physical <= 7:
        return _fail(op, module, "bad_connector", f"connector {physical!r} is not 0..7", connector=None)
    move = "close" if op == "latch" else "open"
    if (module, physical) in s.jammed:  # faults put in from outside (vm.lattice.outside jam, fail)
        return _fail(op, module, "jammed", f"connector {physical} of module {module} is jammed: its "
                     f"latch does not {move}", connector=physical)
    if op == "latch" and (module, physical) in s.failing:
        s.failing = s.failing - {(module, physical)}
        return _fail(op, module, "jammed", f"the latch of connector {physical} of module {module} did "
                     "not close (once)", connector=physical)
    return None


def latch(s: Structure, module: int, physical: int) -> Change:
    bad = _connector(s, "latch", module, physical)
    if bad is not None:
        return bad
    kw = {"connector": physical}
    if physical % 2:
        return _fail("latch", module, "female", f"connector {physical} of module {module} is female "
                     "(odd): only a male (even) connector latches", **kw)
    if physical in s._ports[module]:
        return _fail("latch", module, "in_use", f"connector {physical} of module {module} is latched "
                     "already", **kw)
    other = s.facing(module, physical)
    if other is None:
        return _fail("latch", module, "not_aligned", f"no module faces connector {physical} of "
                     f"module {module}", **kw)
    b, pb = other
    if pb % 2 == 0:
        return _fail("latch", module, "faces_male", f"connector {physical} of module {module} faces "
                     f"male connector {pb} of module {b}", **kw)
    if pb in s._ports[b]:
        return _fail("latch", module, "in_use", f"connector {pb} of module {b} is latched already",
                     **kw)
    s._ports[module][physical] = (b, pb)
    s._ports[b][pb] = (module, physical)
    return _done(s, Change(True, "latch", module, physical, link=_link(module, physical, b, pb)))


def unlatch(s: Structure, module: int, physical: int) -> Change:
    bad = _connector(s, "unlatch", module, physical)
    if bad is not None:
        return bad
    kw = {"connector": physical}
    peer = s._ports[module].get(physical)
    if peer is None:
        return _fail("unlatch", module, "not_latched", f"connector {physical} of module {module} is "
                     "not latched", **kw)
    b, pb = peer
    if physical % 2 and pb % 2 == 0:
        return _fail("unlatch", module, "female", f"connector {physical} of module {module} is female "
                     f"(odd): the male connector {pb} of module {b} unlatches this link", **kw)
    del s._ports[module][physical]
    del s._ports[b][pb]
    parts = ()
    left = s.part_of(module)
    if b not in left:
        parts = tuple(sorted((left, s.part_of(b)), key=min))
    return _done(s, Change(True, "unlatch", module, physical, link=_link(module, physical, b, pb),
                           parts=parts))


def _link(a: int, pa: int, b: int, pb: int) -> Link:
    from vm.lattice.structure import Link
    return Link(a, pa, b, pb) if a < b else Link(b, pb, a, pa)


# ---- rotation ------------------------------------------------------------------------------
def sides(s: Structure, module: int) -> tuple[frozenset[int], frozenset[int]]:
    """The modules reached through the north (0-3) and through the south (4-7) hemisphere of
    ``module`` without passing it."""
    out = []
    for hemi in (0, 1):
        reached: set[int] = set()
        for p, (b, _) in s._ports[module].items():
            if p // 4 == hemi and b not in reached:
                reached |= s.part_of(b, without=module)
        out.append(frozenset(reached))
    return out[0], out[1]


def _choose_moving(s: Structure, north: frozenset[int], south: frozenset[int]) -> int:
    if not north or not south:
        return 0 if not north else 1
    if s.ground_z is not None:
        grounded = [any(s.modules[m].position[2] == s.ground_z for m in side) for side in (north, south)]
        if grounded[0] != grounded[1]:
            return 1 if grounded[0] else 0
    if len(north) != len(south):
        return 0 if len(north) < len(south) else 1
    return 0


def rotate(s: Structure, module: int, quarters: int, *, moving: int | None = None,
           apply: bool = True) -> Change:
    """Turn ``module``'s joint by ``quarters`` (positive: the joint's positive direction, the north
    hemisphere turning about the module's north axis by the right-hand rule). With ``apply`` False
    only check (the world checks at a motion's start and applies at its end)."""
    if module not in s.modules:
        return _fail("rotate", module, "no_module", f"no module {module}", quarters=quarters)
    north, south = sides(s, module)
    kw = {"quarters": quarters}
    loop = north & south
    if loop:
        return _fail("rotate", module, "loop", f"modules {_ids(loop)} hold both hemispheres of module "
                     f"{module} (a loop through the structure)", **kw)
    if moving is None:
        moving = _choose_moving(s, north, south)
    carried = north if moving == 0 else south
    spec = s.modules[module]
    p = placement(spec.axis, spec.mount)
    axis = (p[0][1], p[1][1], p[2][1])
    sign = 1 if moving == 0 else -1  # the south side turns the other way about the same line
    k = sign * quarters
    # more than a full turn sweeps nothing a full turn does not
    hits, low = _sweep(s, spec.position, axis, max(-4, min(4, k)), carried)
    kw["moving"] = moving
    if hits:
        return _fail("rotate", module, "collision", f"module {_ids(frozenset(m for m, _ in hits))} would "
                     f"sweep through {_cells(c for _, c in hits)}",
                     blocked_by=tuple(sorted({c for _, c in hits})), **kw)
    if low is not None:
        return _fail("rotate", module, "ground", f"module {low} would pass below the ground "
                     f"(z {s.ground_z})", **kw)
    change = Change(True, "rotate", module, quarters=quarters, moved=tuple(sorted(carried)), moving=moving)
    if not apply:
        return change
    _move(s, module, axis, k, carried, moving, quarters)
    return _done(s, change)


def _sweep(s: Structure, centre: Vec, axis: Vec, k: int, carried: frozenset[int]
           ) -> tuple[list[tuple[int, Vec]], int | None]:
    hits: list[tuple[int, Vec]] = []
    below = None
    for m in sorted(carried):
        pos = s.modules[m].position
        offset = (pos[0] - centre[0], pos[1] - centre[1], pos[2] - centre[2])
        cells, lowest = motion.swept(offset, axis, 90.0 * k, (centre[0] % 2, centre[1] % 2, centre[2] % 2))
        for c in sorted(cells):
            cell = (c[0] + centre[0], c[1] + centre[1], c[2] + centre[2])
            other = s._by_position.get(cell)
            if (other is not None and other not in carried) or cell in s.blocked:
                hits.append((m, cell))
        if below is None and s.ground_z is not None and lowest + centre[2] < s.ground_z - 1e-9:
            below = m
    return hits, below


def _move(s: Structure, module: int, axis: Vec, k: int, carried: frozenset[int], moving: int,
          quarters: int) -> None:
    from vm.lattice.structure import directions
    turn = motion.quarter_matrix(axis, k)
    centre = s.modules[module].position
    for m in carried:
        del s._by_position[s.modules[m].position]
    for m in carried:
        spec = s.modules[m]
        d = tuple(a - b for a, b in zip(spec.position, centre, strict=True))
        pos = tuple(a + b for a, b in zip(motion.quarter(axis, k, d), centre, strict=True))  # type: ignore[arg-type]
        new_axis, mount = motion.orientation_of(motion.compose(turn, placement(spec.axis, spec.mount)))
        s.modules[m] = replace(spec, position=pos, axis=new_axis, mount=mount)  # type: ignore[arg-type]
        s._by_position[pos] = m  # type: ignore[index]
    spec = s.modules[module]
    joint = (spec.joint + quarters) % 4
    if moving == 1:  # the south hemisphere turned: the module's frame turned with it
        new_axis, mount = motion.orientation_of(motion.compose(turn, placement(spec.axis, spec.mount)))
        spec = replace(spec, axis=new_axis, mount=mount)
    s.modules[module] = replace(spec, joint=joint)
    for m in (*carried, module):
        s._dirs[m] = directions(s.modules[m])


# ---- adding and removing modules -----------------------------------------------------------
def add(s: Structure, spec: ModuleSpec) -> Change:
    """Put a new module on a free cell; every connector pair facing it is latched, as a
    configuration file joins adjacent modules. It must touch at least one module."""
    from vm.lattice.structure import StructureError, _check_module, directions
    mid = spec.id
    if mid in s.modules:
        return _fail("add", mid, "occupied", f"module {mid} exists already")
    try:
        _check_module(spec)
    except StructureError as e:
        return _fail("add", mid, "bad_place", str(e))
    other = s._by_position.get(spec.position)
    if other is not None or spec.position in s.blocked:
        return _fail("add", mid, "occupied", f"cell {spec.position} is taken"
                     + (f" by module {other}" if other is not None else " (an obstacle)"))
    dirs = directions(spec)
    contacts = []
    for p, d in enumerate(dirs):
        b = s._by_position.get(tuple(a + c for a, c in zip(spec.position, d, strict=True)))  # type: ignore[arg-type]
        if b is not None:
            pb = s._dirs[b].index((-d[0], -d[1], -d[2]))
            if pb in s._ports[b]:
                continue
            contacts.append((p, b, pb))
    if not contacts:
        return _fail("add", mid, "no_contact", f"no free connector of another module faces cell "
                     f"{spec.position}")
    s.modules[mid] = spec
    s._by_position[spec.position] = mid
    s._dirs[mid] = dirs
    s._ports[mid] = {}
    for p, b, pb in contacts:
        s._ports[mid][p] = (b, pb)
        s._ports[b][pb] = (mid, p)
    return _done(s, Change(True, "add", mid, moved=(mid,)))


def remove(s: Structure, module: int) -> Change:
    """Take a module out of the structure (its links open); the parts its neighbours are left in."""
    if module not in s.modules:
        return _fail("remove", module, "no_module", f"no module {module}")
    if module == s.entry:
        return _fail("remove", module, "bad_place", f"module {module} is the entry module: it defines "
                     "the frame and stays")
    neighbours = sorted({b for b, _ in s._ports[module].values()})
    for b, pb in s._ports[module].values():
        del s._ports[b][pb]
    del s._ports[module]
    del s._by_position[s.modules[module].position]
    del s.modules[module]
    del s._dirs[module]
    parts: list[frozenset[int]] = []
    for b in neighbours:
        if not any(b in part for part in parts):
            parts.append(s.part_of(b))
    split = tuple(sorted(parts, key=min)) if len(parts) > 1 else ()
    return _done(s, Change(True, "remove", module, parts=split))


def _ids(ids: frozenset[int]) -> str:
    return ", ".join(str(m) for m in sorted(ids))


def _cells(cells: object) -> str:
    return ", ".join(str(c) for c in sorted(set(cells)))  # type: ignore[call-overload]
