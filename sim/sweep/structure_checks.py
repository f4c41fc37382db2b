"""Success criteria on the final structure of a run: ``[success.structure]``.

    [success.structure]
    shape = "car7"              # the final cells and connections are car7's (see below)
    parts = 1                   # the robot ends in one part (2: a split in two, ...)
    modules = 6                 # this many modules are left (an outside detach takes one away)
    connected = [[0, 1], [1, 3]]  # these modules are latched to each other at the end

``shape`` names a configuration as ``rdcd simulate --config`` does (a file beside the experiment,
a shipped name, snakeN, randomN-seedS). The final structure has that shape when some turn of the
lattice (one of its 24 rotations) and a shift that puts the entry module on the configuration's
entry cell make the two agree: the same occupied cells, and the same pairs of cells latched to
each other. Module ids do not matter (a reconfiguration may end with other modules on the car's
cells); the axis of a module follows from its cell, so orientations agree with the cells.

Each key is a criterion of its own (``structure_shape``, ``structure_parts``,
``structure_modules``, ``structure_connected``), so the summary counts the runs that missed each.
A row keeps the facts (``final``: cells, latched pairs, parts), never the verdict.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

from vm.lattice.structure import Structure

KEYS = ("shape", "parts", "modules", "connected")
MAX_PAIRS = 10_000

Cell = tuple[int, int, int]


@dataclass(frozen=True)
class Shape:
    """A structure's cells and latched cell pairs, the entry cell apart."""

    name: str
    entry: Cell
    cells: frozenset[Cell]
    links: frozenset[frozenset[Cell]]


@dataclass(frozen=True)
class StructureCheck:
    key: str  # one of KEYS
    expected: Any  # Shape, int, or a tuple of (a, b) module pairs

    @property
    def criterion(self) -> str:
        return f"structure_{self.key}"

    def describe(self) -> str:
        if self.key == "shape":
            return f"the final structure has {self.expected.name}'s shape"
        if self.key == "connected":
            return "latched at the end: " + ", ".join(f"{a}-{b}" for a, b in self.expected)
        return f"{self.expected} {self.key} at the end" if self.key == "modules" else \
            f"{self.expected} part{'s' if self.expected != 1 else ''} at the end"


def shape_of(structure: Structure, name: str) -> Shape:
    cells = {m: s.position for m, s in structure.modules.items()}
    return Shape(name, cells[structure.entry], frozenset(cells.values()),
                 frozenset(frozenset((cells[k.a], cells[k.b])) for k in structure.links()))


def parse_structure(table: Any, load_shape: Any) -> tuple[tuple[StructureCheck, ...], str | None]:
    """The checks of ``[success.structure]``, or the problem (``key: message``). ``load_shape``
    turns a configuration name into a ``Shape`` or raises ``ValueError`` with a one-line reason."""
    if not isinstance(table, dict):
        return (), "success.structure: must be a table (shape, parts, modules, connected)"
    checks = []
    for key, raw in table.items():
        where = f"success.structure.{key}"
        if key not in KEYS:
            return (), f"{where}: unknown key (known: {', '.join(KEYS)})"
        if key == "shape":
            if not isinstance(raw, str) or not raw:
                return (), f"{where}: must name a configuration, e.g. \"car7\""
            try:
                checks.append(StructureCheck(key, load_shape(raw)))
            except ValueError as error:
                return (), f"{where}: {error}"
        elif key in ("parts", "modules"):
            if isinstance(raw, bool) or not isinstance(raw, int) or not 1 <= raw <= 100_000:
                return (), f"{where}: must be a whole number from 1 (not {raw!r})"
            checks.append(StructureCheck(key, raw))
        else:
            pairs = _pairs(raw)
            if pairs is None:
                return (), f"{where}: must be a list of module pairs, e.g. [[0, 1], [1, 3]]"
            checks.append(StructureCheck(key, pairs))
    return tuple(checks), None


def _pairs(raw: Any) -> tuple[tuple[int, int], ...] | None:
    if not isinstance(raw, list) or not raw or len(raw) > MAX_PAIRS:
        return None
    out = []
    for pair in raw:
        if (not isinstance(pair, list) or len(pair) != 2 or pair[0] == pair[1] or not all(
                isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 10_000 for v in pair)):
            return None
        out.append((min(pair), max(pair)))
    return tuple(out)


def facts(report: dict[str, Any]) -> dict[str, Any]:
    """What a row keeps: each remaining module's final cell, the latched module pairs, the parts."""
    return {"cells": [[m["id"], *m["final_lattice"]] for m in report["modules"]
                      if m.get("final_lattice") is not None],
            "links": [list(pair) for pair in  # lists: a row is JSON
                      sorted({(min(c[0], c[2]), max(c[0], c[2])) for c in report.get("connections", [])})],
            "parts": len(report.get("parts") or [1])}


def failures(final: dict[str, Any] | None, checks: tuple[StructureCheck, ...]) -> list[str]:
    """The criteria of ``checks`` a row's facts miss (every one when it has no facts: an old row)."""
    if not checks:
        return []
    if not final or "cells" not in final:
        return [c.criterion for c in checks]
    cells = {m[0]: tuple(m[1:]) for m in final["cells"]}
    links = {tuple(pair) for pair in final["links"]}
    missed = []
    for check in checks:
        if check.key == "parts":
            ok = final["parts"] == check.expected
        elif check.key == "modules":
            ok = len(cells) == check.expected
        elif check.key == "connected":
            ok = all(pair in links for pair in check.expected)
        else:
            ok = _same_shape(cells, links, final["entry"], check.expected)
        if not ok:
            missed.append(check.criterion)
    return missed


def _same_shape(cells: dict[int, Cell], links: set[tuple[int, ...]], entry: int, shape: Shape) -> bool:
    if entry not in cells or len(cells) != len(shape.cells) or len(links) != len(shape.links):
        return False
    origin = cells[entry]
    for turn in ROTATIONS:
        moved = {m: _add(_apply(turn, _sub(c, origin)), shape.entry) for m, c in cells.items()}
        if set(moved.values()) != shape.cells:
            continue
        if {frozenset((moved[a], moved[b])) for a, b in links} == shape.links:
            return True
    return False


def _rotations() -> tuple[tuple[tuple[int, int, int], ...], ...]:
    """The 24 turns of the cubic lattice: signed permutation matrices of determinant 1."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            rows = tuple(tuple(signs[i] if j == perm[i] else 0 for j in range(3)) for i in range(3))
            if _det(rows) == 1:
                out.append(rows)
    return tuple(out)


def _det(m: tuple[tuple[int, int, int], ...]) -> int:
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _apply(m: tuple[tuple[int, int, int], ...], v: Cell) -> Cell:
    return (sum(m[0][j] * v[j] for j in range(3)), sum(m[1][j] * v[j] for j in range(3)),
            sum(m[2][j] * v[j] for j in range(3)))


def _sub(a: Cell, b: Cell) -> Cell:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _add(a: Cell, b: Cell) -> Cell:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


ROTATIONS = _rotations()
