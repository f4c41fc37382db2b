"""One pose sample of every module: centre (mm), each hemisphere's rotation since the module
appeared, and whether it is in the world (``sim.replay.recording.CHANNELS``).

The physics world reads its links (their frames are aligned with the lattice when the module is
created, so a link's orientation is the rotation it made since). The lattice world reads the
structure (``vm.lattice.structure``): each physical hemisphere's placement (``sim.frames``) now
against the one it had when the module appeared. A quarter turn under way
(``LatticeWorld.turning``) turns the moving hemisphere and every module it carries about the
turning module's axis by the angle turned so far, so the modules go round to their new cells; the
structure moves them exactly when the turn ends. A joint angle the structure does not hold (the
older joint commands, a wheel) turns the south hemisphere about its own pole, as always.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from sim import geometry as g
from sim import params
from sim.frames import hemi_placement
from sim.replay.recording import quantise_quaternion
from sim.shapes import matrix_to_quat
from vm.lattice.joint import wrap
from vm.lattice.structure import ModuleSpec

ABSENT = [0] * 11 + [0]


def _mm(v: float) -> int:
    return max(-32767, min(32767, round(v * 1000)))


def physics_sampler(world: Any, ids: list[int]) -> Callable[[], list[int]]:
    import pybullet as pb

    from sim.poses import quat_matrix, to_world

    client = world.client
    last: dict[int, list[int]] = {}  # a module taken away keeps its last pose (shown absent)
    seen: list[Any] = [None, [], []]  # the robot the link lists below were made for

    def sample() -> list[int]:
        robot = world.robot
        if seen[0] is not robot:  # new bodies after a change of shape
            here = [robot.modules[mid] for mid in ids if mid in robot.modules]
            seen[:] = [robot, here, [(b, sorted({mb.links[s] for mb in here if mb.body == b
                                                  for s in (g.PLUS, g.MINUS)})) for b in robot.bodies]]
        states = {(b, link): st for b, links in seen[2] if links
                  for link, st in zip(links, pb.getLinkStates(b, links, physicsClientId=client), strict=True)}
        present = set()
        for mb in seen[1]:
            plus, minus = states[(mb.body, mb.links[g.PLUS])], states[(mb.body, mb.links[g.MINUS])]
            centre = to_world((plus[4], quat_matrix(plus[5])), mb.offsets[g.PLUS])
            last[mb.id] = [_mm(centre[0]), _mm(centre[1]), _mm(centre[2])] + \
                _turned(plus[5], mb.frames.get(g.PLUS)) + _turned(minus[5], mb.frames.get(g.MINUS))
            present.add(mb.id)
        row: list[int] = []
        for mid in ids:
            row += last[mid] + [1] if mid in present else (last[mid] + [0] if mid in last else ABSENT)
        return row
    return sample


def _turned(q: tuple[float, float, float, float], frame: Any) -> list[int]:
    """A hemisphere's rotation since the start: its link's, and its own turn in the link."""
    if frame is None:
        return quantise_quaternion(q)
    from sim.poses import quat_matrix

    return quantise_quaternion(matrix_to_quat(np.array(quat_matrix(q)) @ np.array(frame)))


def _about(axis: np.ndarray, degrees: float) -> np.ndarray:
    """Rotation by ``degrees`` about the unit ``axis`` (right-hand rule)."""
    a = math.radians(degrees)
    x, y, z = axis
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]], dtype=float)
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)


def _quat(m: np.ndarray) -> list[int]:
    return quantise_quaternion(matrix_to_quat(m))


def _qmul(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float, float]:
    """The rotation b then a, (x, y, z, w) quaternions."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def lattice_sampler(world: Any, ids: list[int], specs: dict[int, ModuleSpec]) -> Callable[[], list[int]]:
    """``specs``: each module as it first appears (the frame its hemispheres are drawn in)."""
    s = world.structure
    u = params.LATTICE_UNIT
    lift = params.RING_RADIUS - min(spec.position[2] for spec in specs.values()) * u
    # per module: start placement of each viewer half (PLUS, MINUS) and which physical hemisphere it is
    halves = {}
    for mid, spec in specs.items():
        north = g.physical_side(spec, 0)
        order = (0, 1) if north == g.PLUS else (1, 0)
        halves[mid] = [(h, hemi_placement(spec, h).T) for h in order]
    last: dict[int, list[int]] = {}
    cache: dict[int, tuple[Any, list[int]]] = {}
    carried: dict[int, tuple[int, tuple[int, ...], int]] = {}  # turning module -> (version, moved, moving)

    def motions() -> dict[int, tuple[np.ndarray, np.ndarray, float, int, float]]:
        """Module -> (pivot, north axis, degrees seen, hemisphere moving or -1 when carried, degrees
        of its own joint) of the turns under way."""
        out = {}
        for mid, (quarters, moving, degrees) in world.turning().items():
            spec = s.modules.get(mid)
            if spec is None:
                continue
            known = carried.get(mid)
            if known is None or known[0] != s.version:
                check = s.rotate(mid, quarters, moving=moving, apply=False)
                known = carried[mid] = (s.version, tuple(check.moved), check.moving or 0)
            pivot = np.array(spec.position, dtype=float)
            n = hemi_placement(spec, 1)[:, 1]
            # the south hemisphere turning is the north one turning the other way about n
            turn = (pivot, n, degrees if known[2] == 0 else -degrees, known[2], degrees)
            out[mid] = turn
            for other in known[1]:
                out[other] = (*turn[:3], -1, 0.0)  # -1: the whole module is carried
        return out

    def pose(mid: int, spec: ModuleSpec, motion: Any, extra: float) -> list[int]:
        if motion is None:
            return still(mid, spec, extra)
        centre = np.array(spec.position, dtype=float)
        placements = {h: hemi_placement(spec, h) for h in (0, 1)}
        n = placements[1][:, 1]
        if extra:
            placements[1] = _about(n, -extra) @ placements[1]
        pivot, axis, degrees, moving, _ = motion
        turn = _about(axis, degrees)
        if moving == -1:
            centre = pivot + turn @ (centre - pivot)
            placements = {h: turn @ p for h, p in placements.items()}
        else:
            placements[moving] = turn @ placements[moving]
        x, y, z = centre * u
        out = [_mm(x), _mm(y), _mm(z + lift)]
        for h, start in halves[mid]:
            out += _quat(placements[h] @ start)
        return out + [1]

    bases: dict[int, tuple[int, Any]] = {}  # module -> (structure version, its pose at rest)

    def still(mid: int, spec: ModuleSpec, extra: float) -> list[int]:
        """No turn carries it: the structure's pose, the south hemisphere turned by ``extra`` about
        its pole (quaternion arithmetic: a wheel turns every sample)."""
        base = bases.get(mid)
        if base is None or base[0] != s.version:
            x, y, z = np.array(spec.position, dtype=float) * u
            rest = [(h, matrix_to_quat(hemi_placement(spec, h) @ start)) for h, start in halves[mid]]
            base = bases[mid] = (s.version, ([_mm(x), _mm(y), _mm(z + lift)],
                                             [(h, q, quantise_quaternion(q)) for h, q in rest],
                                             tuple(hemi_placement(spec, 1)[:, 1])))
        centre, rest, (nx, ny, nz) = base[1]
        half = math.radians(-extra) / 2
        sn, c = math.sin(half) * 32767, math.cos(half) * 32767
        turn = (nx * sn, ny * sn, nz * sn, c)
        out = list(centre)
        for h, q, quantised in rest:
            if h == 1 and extra:  # a unit quaternion times 32767: as quantise_quaternion, w >= 0
                turned = _qmul(turn, q)
                sign = -1 if turned[3] < 0 else 1
                out += [round(sign * v) for v in turned]
            else:
                out += quantised
        return out + [1]

    def sample() -> list[int]:
        moving = motions()
        row: list[int] = []
        for mid in ids:
            spec = s.modules.get(mid)
            if spec is None:
                row += last[mid][:11] + [0] if mid in last else ABSENT
                continue
            motion = moving.get(mid)
            own = motion[4] if motion is not None else 0.0  # the joint angle its own turn made
            extra = round(wrap(world.hals[mid].joint_angle_deg() - own - 90.0 * spec.joint), 6)
            key = (s.version, extra, motion[2] if motion is not None else None)
            hit = cache.get(mid)
            if hit is None or hit[0] != key:
                hit = cache[mid] = (key, pose(mid, spec, motion, extra))
            last[mid] = hit[1]
            row += hit[1]
        return row
    return sample
