"""The geometry of a quarter turn: integer rotations about a module's axis, the orientation a
carried module ends with, and the lattice cells a carried module sweeps through.

Lattice units: a module's centre is an integer point whose parity gives its axis (docs/vm.md);
neighbours are a diagonal step (length sqrt 2) apart. A carried module's centre moves on a circle
about the turning module's axis line. The cells it *sweeps* are the cells whose Voronoi region
(the points nearer to that cell's centre than to any other cell's) the centre passes through,
sampled every ``SAMPLE_DEG`` degrees: the usual "swept cells" of lattice planners. A neighbour of
the turning module sweeps only its start and end cells; a module two steps out also sweeps the
cell on the diagonal between them.
"""

from __future__ import annotations

import math
from functools import lru_cache

from vm import navigation
from vm.lattice.geometry import Matrix, Vec, placement
from vm.lattice.mount import ALL_MOUNTS, Mount

SAMPLE_DEG = 5.0


def dot(a: Vec, b: Vec) -> int:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def quarter(axis: Vec, k: int, v: Vec) -> Vec:
    """``v`` turned ``k`` quarter turns about the unit vector ``axis`` (right-hand rule)."""
    for _ in range(k % 4):
        along = dot(axis, v)
        c = cross(axis, v)
        v = (along * axis[0] + c[0], along * axis[1] + c[1], along * axis[2] + c[2])
    return v


def quarter_matrix(axis: Vec, k: int) -> Matrix:
    cols = [quarter(axis, k, e) for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    return tuple(tuple(cols[j][i] for j in range(3)) for i in range(3))  # type: ignore[return-value]


def compose(a: Matrix, b: Matrix) -> Matrix:
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3))
                 for i in range(3))  # type: ignore[return-value]


# every proper rotation of the lattice is the placement of exactly one (axis, mount)
_ORIENTATIONS: dict[Matrix, tuple[int, Mount]] = {
    placement(axis, mount): (axis, mount) for axis in navigation.AXES for mount in ALL_MOUNTS}


def orientation_of(m: Matrix) -> tuple[int, Mount]:
    """The (axis, mount) whose placement is ``m``."""
    return _ORIENTATIONS[m]


def _is_cell(p: Vec) -> bool:
    return navigation.axis_for_position(*p) is not None


@lru_cache(maxsize=4096)
def swept(offset: Vec, axis: Vec, degrees: float, parity: Vec) -> tuple[frozenset[Vec], float]:
    """Cells (relative to the turning module's centre, whose coordinates mod 2 are ``parity``)
    swept by a module at ``offset`` turned by ``degrees`` about ``axis`` through the centre, and
    the lowest z (relative) its centre reaches."""
    along = dot(axis, offset)
    base = (offset[0] - along * axis[0], offset[1] - along * axis[1], offset[2] - along * axis[2])
    side = cross(axis, offset)
    steps = max(1, math.ceil(abs(degrees) / SAMPLE_DEG))
    cells: set[Vec] = set()
    lowest = float(offset[2])
    for i in range(steps + 1):
        t = math.radians(degrees * i / steps)
        c, s = math.cos(t), math.sin(t)
        p = tuple(along * axis[j] + c * base[j] + s * side[j] for j in range(3))
        lowest = min(lowest, p[2])
        cells |= _nearest_cells(p, parity)  # type: ignore[arg-type]
    return frozenset(cells), lowest


def _nearest_cells(p: tuple[float, float, float], parity: Vec) -> set[Vec]:
    r = tuple(round(c) for c in p)
    best, out = math.inf, set()
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                q = (r[0] + dx, r[1] + dy, r[2] + dz)
                if not _is_cell((q[0] + parity[0], q[1] + parity[1], q[2] + parity[2])):
                    continue
                d = (q[0] - p[0]) ** 2 + (q[1] - p[1]) ** 2 + (q[2] - p[2]) ** 2
                if d < best - 1e-9:
                    best, out = d, {q}
                elif d <= best + 1e-9:
                    out.add(q)
    return out
