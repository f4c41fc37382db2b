"""A structure: ATRON modules on lattice places, with their mounts and connections — the world's
one truth about shape (docs/simulator.md "Structures that change").

Validation at construction (``StructureError`` names the offending module): lattice parity of
each position against its axis (docs/vm.md), no two modules in one place, coordinates that fit
the packets' signed bytes, explicit connections only between adjacent modules, a connected whole,
and an entry module at the origin with axis NS and the identity mount (it defines the frame).

After construction the structure changes only through its operations (``vm.lattice.changes``):
latch, unlatch, rotate, add, remove. Each is checked there and returns a ``Change``; an
impossible operation is a failed ``Change``, never an exception.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any

from vm import navigation
from vm.lattice import changes
from vm.lattice.geometry import placement
from vm.lattice.motion import quarter
from vm.lattice.mount import IDENTITY, Mount

EW, NS, UD = navigation.EAST_WEST, navigation.NORTH_SOUTH, navigation.UP_DOWN
AXIS_NAMES = navigation.AXIS_NAMES

Vec = tuple[int, int, int]


class StructureError(ValueError):
    """An invalid structure; the message is one line naming the offending module."""


@dataclass(frozen=True, slots=True)
class ModuleSpec:
    id: int
    position: Vec
    axis: int
    mount: Mount = IDENTITY
    # quarter turns (0..3) the physical north hemisphere (connectors 0-3) is turned from the south
    # one, in the positive joint direction; 0 in every configuration file
    joint: int = 0


@dataclass(frozen=True, slots=True)
class Link:
    """Two connected modules and the physical connector of each that touches the other."""

    a: int
    a_physical: int
    b: int
    b_physical: int


@dataclass(frozen=True)
class Snapshot:
    modules: dict[int, ModuleSpec]
    ports: dict[int, dict[int, tuple[int, int]]]
    version: int


@lru_cache(maxsize=8192)  # pure in a frozen spec; planners and the checker call it often
def directions(spec: ModuleSpec) -> tuple[Vec, ...]:
    """Structure-frame offset each physical connector 0..7 faces (the north ring turned by the
    joint's quarters about the module's north axis)."""
    base = [navigation.offset(spec.axis, spec.mount.virtual_of(p)) for p in range(8)]
    if spec.joint % 4:
        north = placement(spec.axis, spec.mount)
        axis = (north[0][1], north[1][1], north[2][1])  # body +y in the structure frame
        base[:4] = [quarter(axis, spec.joint, d) for d in base[:4]]
    return tuple(base)


_PARITY_TEXT = {NS: "x, y, z all even", EW: "x, y odd and z even", UD: "y, z odd and x even"}


def describe(spec: ModuleSpec) -> str:
    return f"module {spec.id} at {tuple(spec.position)}"


@dataclass
class Structure:
    """Modules by id, validated on construction (use ``make_structure``). ``neighbours`` and
    ``links`` give, for each latched connection, the physical connector of each side.

    It changes only through ``latch``, ``unlatch``, ``rotate``, ``add`` and ``remove`` (each
    returns a ``vm.lattice.changes.Change``; callbacks in ``listeners`` hear every change that
    happened). ``ground_z``: the lowest z a module's centre may reach (the plane under the lowest
    module at construction; None: no ground). ``blocked``: cells no module may enter or sweep
    through (a world's obstacles). ``jammed``: (module, physical connector) pairs whose latch
    does not move — it neither closes nor opens; ``failing``: pairs whose latch does not close
    the next time it is asked to, once (faults put in from outside: ``vm.lattice.outside``, jam and fail)."""

    modules: dict[int, ModuleSpec]
    entry: int
    name: str = ""
    explicit_connections: frozenset[frozenset[int]] | None = None
    expected_roles: dict[int, str | None] = field(default_factory=dict)
    _by_position: dict[Vec, int] = field(init=False, repr=False)
    _ports: dict[int, dict[int, tuple[int, int]]] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._by_position = {}
        for spec in self.modules.values():
            _check_module(spec)
            other = self._by_position.get(spec.position)
            if other is not None:
                raise StructureError(f"{describe(spec)}: place already taken by module {other}")
            self._by_position[spec.position] = spec.id
        self._check_entry()
        self._check_explicit()
        self._ports = {mid: {} for mid in self.modules}
        for link in self._adjacent_links():
            self._ports[link.a][link.a_physical] = (link.b, link.b_physical)
            self._ports[link.b][link.b_physical] = (link.a, link.a_physical)
        self._check_connected()
        self._dirs = {mid: directions(spec) for mid, spec in self.modules.items()}
        self.ground_z: int | None = min(spec.position[2] for spec in self.modules.values())
        self.blocked: frozenset[Vec] = frozenset()
        self.jammed: frozenset[tuple[int, int]] = frozenset()
        self.failing: frozenset[tuple[int, int]] = frozenset()
        self.listeners: list[Callable[[Any], None]] = []
        self.version = 0  # counts the changes that happened

    # --- queries -------------------------------------------------------------------------
    def ids(self) -> list[int]:
        return list(self.modules)

    def neighbours(self, module_id: int) -> dict[int, tuple[int, int]]:
        """physical connector -> (neighbour id, the neighbour's physical connector)."""
        return dict(self._ports[module_id])

    def connected_channels(self, module_id: int) -> frozenset[int]:
        return frozenset(self._ports[module_id])

    def links(self) -> list[Link]:
        out = []
        for a, ports in self._ports.items():
            for pa, (b, pb) in sorted(ports.items()):
                if a < b:
                    out.append(Link(a, pa, b, pb))
        return sorted(out, key=lambda k: (k.a, k.a_physical))

    def physical_direction(self, module_id: int, physical: int) -> Vec:
        """Lattice offset, in the structure frame, that physical connector ``physical`` faces."""
        return self._dirs[module_id][physical]

    def module_at(self, cell: Vec) -> int | None:
        return self._by_position.get(tuple(cell))  # type: ignore[arg-type]

    def facing(self, module_id: int, physical: int) -> tuple[int, int] | None:
        """(module, its physical connector) that faces connector ``physical`` of ``module_id``
        across the adjacent cell, latched or not; None if that cell is empty."""
        spec = self.modules[module_id]
        d = self._dirs[module_id][physical]
        other = self._by_position.get((spec.position[0] + d[0], spec.position[1] + d[1],
                                       spec.position[2] + d[2]))
        if other is None:
            return None
        back = (-d[0], -d[1], -d[2])
        return other, self._dirs[other].index(back)

    def physical_map(self, module_id: int) -> tuple[int, ...]:
        """Physical connector at each virtual channel 0..7 (the mount's map when the joint is at
        quarter 0; the north ring turned with the joint otherwise)."""
        spec, dirs = self.modules[module_id], self._dirs[module_id]
        return tuple(dirs.index(navigation.offset(spec.axis, v)) for v in range(8))

    def parts(self) -> list[frozenset[int]]:
        """The connected parts (by latched links), each once, ordered by their lowest id."""
        seen: set[int] = set()
        out = []
        for mid in sorted(self.modules):
            if mid not in seen:
                part = self.part_of(mid)
                seen |= part
                out.append(part)
        return out

    def part_of(self, module_id: int, *, without: int | None = None) -> frozenset[int]:
        """Modules reachable from ``module_id`` over latched links (not passing ``without``)."""
        seen = {module_id}
        todo = [module_id]
        while todo:
            for other, _ in self._ports[todo.pop()].values():
                if other not in seen and other != without:
                    seen.add(other)
                    todo.append(other)
        return frozenset(seen)

    def free_hemisphere(self, module_id: int) -> int | None:
        """0 if only the physical north hemisphere (connectors 0-3) is unconnected, 1 if only the
        south one (4-7) is; None otherwise. A wheel's rubber ring sits on its free hemisphere."""
        used = {p // 4 for p in self._ports[module_id]}
        free = {0, 1} - used
        return free.pop() if len(free) == 1 else None

    # --- operations (checked in vm.lattice.changes) ----------------------------------------
    def latch(self, module_id: int, physical: int) -> Any:
        return changes.latch(self, module_id, physical)

    def unlatch(self, module_id: int, physical: int) -> Any:
        return changes.unlatch(self, module_id, physical)

    def rotate(self, module_id: int, quarters: int, *, moving: int | None = None,
               apply: bool = True) -> Any:
        return changes.rotate(self, module_id, quarters, moving=moving, apply=apply)

    def add(self, spec: ModuleSpec) -> Any:
        return changes.add(self, spec)

    def remove(self, module_id: int) -> Any:
        return changes.remove(self, module_id)

    def snapshot(self) -> Snapshot:
        """Everything that changes, to give back to ``restore`` (the debugger's step back)."""
        return Snapshot(dict(self.modules), {m: dict(p) for m, p in self._ports.items()}, self.version)

    def copy(self) -> Structure:
        """An independent structure in the same shape (no listeners): a run changes its own."""
        clone = copy.copy(self)
        clone.listeners = []
        clone.restore(self.snapshot())
        return clone

    def restore(self, snap: Snapshot) -> None:
        self.modules = dict(snap.modules)
        self._ports = {m: dict(p) for m, p in snap.ports.items()}
        self._by_position = {spec.position: mid for mid, spec in self.modules.items()}
        self._dirs = {mid: directions(spec) for mid, spec in self.modules.items()}
        self.version = snap.version

    def check_invariants(self) -> None:
        """Raise AssertionError if two modules share a cell or a link does not join two facing
        connectors of adjacent modules (tests call this after every operation)."""
        cells = [spec.position for spec in self.modules.values()]
        assert len(set(cells)) == len(cells), "two modules in one cell"
        assert self._by_position == {s.position: m for m, s in self.modules.items()}
        for spec in self.modules.values():
            _check_module(spec)
        for a, ports in self._ports.items():
            for pa, (b, pb) in ports.items():
                assert self._ports[b].get(pb) == (a, pa), f"link {a}.{pa}-{b}.{pb} one-sided"
                assert self.facing(a, pa) == (b, pb), f"link {a}.{pa}-{b}.{pb} does not face"

    # --- validation ----------------------------------------------------------------------
    def _check_entry(self) -> None:
        spec = self.modules.get(self.entry)
        if spec is None:
            raise StructureError(f"entry module {self.entry}: no such module")
        if spec.position != (0, 0, 0) or spec.axis != NS or spec.mount != IDENTITY:
            raise StructureError(
                f"{describe(spec)}: the entry module defines the frame, so it must sit at (0, 0, 0) "
                "with axis NS and mount rotation 0, not mirrored")

    def _adjacent_links(self) -> Iterable[Link]:
        for spec in self.modules.values():
            for v in range(8):
                rx, ry, rz, raxis, rvch = navigation.receiver(*spec.position, spec.axis, v)
                other = self._by_position.get((rx, ry, rz))
                if other is None or other <= spec.id:
                    continue
                o = self.modules[other]
                if o.axis != raxis:  # unreachable for valid parity; guards the table
                    raise StructureError(f"{describe(o)}: axis does not match its neighbour {spec.id}")
                if self.explicit_connections is not None and \
                        frozenset((spec.id, other)) not in self.explicit_connections:
                    continue
                yield Link(spec.id, spec.mount.physical_of(v), other, o.mount.physical_of(rvch))

    def _check_explicit(self) -> None:
        for pair in sorted(self.explicit_connections or (), key=sorted):
            ends = sorted(pair)
            a, b = (ends[0], ends[0]) if len(ends) == 1 else ends
            for m in (a, b):
                if m not in self.modules:
                    raise StructureError(f"connection {a}-{b}: no module {m}")
            spec = self.modules[a]
            near = {navigation.receiver(*spec.position, spec.axis, v)[:3] for v in range(8)}
            if a == b or self.modules[b].position not in near:
                raise StructureError(
                    f"{describe(spec)}: listed connection to module {b}, which is not on an adjacent place")

    def _check_connected(self) -> None:
        seen = {self.entry}
        todo = [self.entry]
        while todo:
            for other, _ in self._ports[todo.pop()].values():
                if other not in seen:
                    seen.add(other)
                    todo.append(other)
        for mid, spec in self.modules.items():
            if mid not in seen:
                raise StructureError(f"{describe(spec)}: not connected to the entry module {self.entry}")


def _check_module(spec: ModuleSpec) -> None:
    if spec.axis not in AXIS_NAMES:
        raise StructureError(f"{describe(spec)}: unknown axis {spec.axis!r} (use EW, NS or UD)")
    if len(spec.position) != 3 or not all(isinstance(c, int) for c in spec.position):
        raise StructureError(f"{describe(spec)}: position must be three integers")
    if not all(-128 <= c <= 127 for c in spec.position):
        raise StructureError(f"{describe(spec)}: coordinates must lie in -128..127 (packets carry bytes)")
    if navigation.axis_for_position(*spec.position) != spec.axis:
        name = AXIS_NAMES[spec.axis]
        raise StructureError(f"{describe(spec)}: axis {name} needs {_PARITY_TEXT[spec.axis]}")


def make_structure(modules: Sequence[ModuleSpec], *, entry: int | None = None, name: str = "",
                   connections: Iterable[tuple[int, int]] | None = None,
                   expected_roles: dict[int, str | None] | None = None) -> Structure:
    """Build and validate a structure; ``entry`` defaults to the first module."""
    by_id: dict[int, ModuleSpec] = {}
    for spec in modules:
        if not isinstance(spec.position, tuple):
            spec = replace(spec, position=tuple(spec.position))
        if spec.id in by_id:
            raise StructureError(f"{describe(spec)}: module id {spec.id} used twice")
        by_id[spec.id] = spec
    if not by_id:
        raise StructureError("structure: no modules")
    explicit = None if connections is None else frozenset(frozenset(p) for p in connections)
    return Structure(by_id, modules[0].id if entry is None else entry, name, explicit,
                     dict(expected_roles or {}))
