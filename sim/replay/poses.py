"""One pose sample of every module: centre (mm) and each hemisphere's rotation since the start.

The physics world reads its links (their frames are aligned with the lattice at the start, so a
link's orientation is the rotation it made since); the lattice world does not move modules, so
the centre is fixed and only the hemisphere holding the physical south connectors (4-7) turns,
by the joint angle about its own pole (the sign convention of ``sim.robot``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from sim import geometry as g
from sim import params
from sim.replay.recording import quantise_quaternion
from vm.lattice.structure import Structure

IDENTITY = quantise_quaternion((0.0, 0.0, 0.0, 1.0))


def _mm(v: float) -> int:
    return max(-32767, min(32767, round(v * 1000)))


def physics_sampler(world: Any, structure: Structure) -> Callable[[], list[int]]:
    import pybullet as pb

    from sim.poses import quat_matrix, to_world

    order = sorted(structure.modules)
    client = world.client
    last: dict[int, list[int]] = {}  # a module taken away keeps its last pose
    seen: list[Any] = [None, [], []]  # the robot the link lists below were made for

    def sample() -> list[int]:
        robot = world.robot
        if seen[0] is not robot:  # new bodies after a change of shape
            here = [robot.modules[mid] for mid in order if mid in robot.modules]
            seen[:] = [robot, here, [(b, sorted({mb.links[s] for mb in here if mb.body == b
                                                  for s in (g.PLUS, g.MINUS)})) for b in robot.bodies]]
        states = {(b, link): st for b, links in seen[2]
                  for link, st in zip(links, pb.getLinkStates(b, links, physicsClientId=client), strict=True)}
        for mb in seen[1]:
            plus, minus = states[(mb.body, mb.links[g.PLUS])], states[(mb.body, mb.links[g.MINUS])]
            centre = to_world((plus[4], quat_matrix(plus[5])), mb.offsets[g.PLUS])
            last[mb.id] = [_mm(centre[0]), _mm(centre[1]), _mm(centre[2])] + \
                _turned(plus[5], mb.frames.get(g.PLUS)) + _turned(minus[5], mb.frames.get(g.MINUS))
        return [v for mid in order for v in last[mid]]
    return sample


def _turned(q: tuple[float, float, float, float], frame: Any) -> list[int]:
    """A hemisphere's rotation since the start: its link's, and its own turn in the link."""
    if frame is None:
        return quantise_quaternion(q)
    import numpy as np

    from sim.poses import quat_matrix
    from sim.shapes import matrix_to_quat

    return quantise_quaternion(matrix_to_quat(np.array(quat_matrix(q)) @ np.array(frame)))


def lattice_sampler(world: Any, structure: Structure) -> Callable[[], list[int]]:
    order = sorted(structure.modules)
    u = params.LATTICE_UNIT
    lift = params.RING_RADIUS - min(s.position[2] for s in structure.modules.values()) * u
    fixed = []
    for mid in order:
        spec = structure.modules[mid]
        centre = g.lattice_to_world(spec.position)
        south = g.physical_side(spec, 4)
        pole = g.hemisphere_pole(spec.axis, south)
        fixed.append(([_mm(centre[0]), _mm(centre[1]), _mm(centre[2] + lift)], south, pole, world.hals[mid]))

    parts: list[tuple[float, list[int]]] = [(math.nan, [])] * len(fixed)  # (angle, its 11 numbers)

    def sample() -> list[int]:
        row: list[int] = []
        for i, (centre, south, pole, hal) in enumerate(fixed):
            angle = hal.joint_angle_deg()
            if parts[i][0] != angle:  # most joints stand still most of the time
                half = math.radians(angle) / 2
                s, c = math.sin(half) * 32767, math.cos(half) * 32767
                if c < 0:  # as quantise_quaternion: w >= 0 (the pole is a unit axis, no need to normalise)
                    s, c = -s, -c
                turned = [round(pole[0] * s), round(pole[1] * s), round(pole[2] * s), round(c)]
                parts[i] = (angle, centre + ((turned + IDENTITY) if south == g.PLUS else (IDENTITY + turned)))
            row += parts[i][1]
        return row
    return sample
