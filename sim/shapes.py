"""Shapes and mass of a rigid group of hemispheres (one multibody link).

Each hemisphere is a ``Part``: its module centre (relative to the link frame), axis, virtual side
and kind: ``shell`` (the module's sphere: symmetric about the joint axis, so it can ride on either
hemisphere), ``ring`` (a wheel's rubber ring around its free hemisphere) or ``none``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pybullet as pb

from sim import geometry as g
from sim import params

SHELL_COLOUR = (0.85, 0.85, 0.85, 1.0)
RING_COLOUR = (0.15, 0.15, 0.15, 1.0)


@dataclass(frozen=True)
class Part:
    centre: g.Vec3
    axis: int
    side: int
    kind: str  # shell | ring | none


def z_to(v: g.Vec3) -> tuple[float, float, float, float]:
    """Quaternion turning +z onto the axis-aligned unit vector ``v``."""
    x, y, z = v
    s = float(np.sqrt(0.5))
    if z > 0.5:
        return (0.0, 0.0, 0.0, 1.0)
    if z < -0.5:
        return (1.0, 0.0, 0.0, 0.0)
    if x > 0.5:
        return (0.0, s, 0.0, s)
    if x < -0.5:
        return (0.0, -s, 0.0, s)
    if y > 0.5:
        return (-s, 0.0, 0.0, s)
    return (s, 0.0, 0.0, s)


def ring_centre(part: Part) -> g.Vec3:
    pole = g.hemisphere_pole(part.axis, part.side)
    return g.add(part.centre, g.scale(pole, params.RING_AXIAL_OFFSET + params.RING_WIDTH / 2))


def compound_collision(parts: list[Part], client: int) -> int:
    types, radii, lengths, positions, orientations = [], [], [], [], []
    for p in parts:
        if p.kind == "shell":
            types.append(pb.GEOM_SPHERE)
            radii.append(params.MODULE_RADIUS)
            lengths.append(0.0)
            positions.append(p.centre)
            orientations.append((0.0, 0.0, 0.0, 1.0))
        elif p.kind == "ring":
            types.append(pb.GEOM_CYLINDER)
            radii.append(params.RING_RADIUS)
            lengths.append(params.RING_WIDTH)
            positions.append(ring_centre(p))
            orientations.append(z_to(g.hemisphere_pole(p.axis, p.side)))
    if not types:
        return -1
    return pb.createCollisionShapeArray(types, radii=radii, lengths=lengths,
                                        collisionFramePositions=positions,
                                        collisionFrameOrientations=orientations, physicsClientId=client)


def visual_parts(parts: list[Part]) -> list[Part]:
    """The parts that have a visual shape, in the order of the link's visual shapes."""
    return [p for p in parts if p.kind != "none"]


def compound_visual(parts: list[Part], client: int) -> int:
    shown = visual_parts(parts)
    if not shown:
        return -1
    types = [pb.GEOM_SPHERE if p.kind == "shell" else pb.GEOM_CYLINDER for p in shown]
    return pb.createVisualShapeArray(
        types,
        radii=[params.MODULE_RADIUS if p.kind == "shell" else params.RING_RADIUS for p in shown],
        lengths=[0.0 if p.kind == "shell" else params.RING_WIDTH for p in shown],
        rgbaColors=[SHELL_COLOUR if p.kind == "shell" else RING_COLOUR for p in shown],
        visualFramePositions=[p.centre if p.kind == "shell" else ring_centre(p) for p in shown],
        visualFrameOrientations=[(0.0, 0.0, 0.0, 1.0) if p.kind == "shell"
                                 else z_to(g.hemisphere_pole(p.axis, p.side)) for p in shown],
        physicsClientId=client)


def mass_properties(parts: list[Part]) -> tuple[float, g.Vec3, g.Vec3, tuple[float, float, float, float]]:
    """Mass, centre of mass, principal inertia and the principal frame's orientation."""
    m = params.HEMISPHERE_MASS
    off = params.HEMISPHERE_COM_OFFSET
    coms = [np.array(g.add(p.centre, g.scale(g.hemisphere_pole(p.axis, p.side), off))) for p in parts]
    com = np.mean(coms, axis=0)
    tensor = np.zeros((3, 3))
    for p, c in zip(parts, coms, strict=True):
        d = c - com
        tensor += np.diag(g.hemisphere_inertia(p.axis)) + m * (d @ d * np.eye(3) - np.outer(d, d))
    values, vectors = np.linalg.eigh(tensor)
    if np.linalg.det(vectors) < 0:
        vectors[:, 2] = -vectors[:, 2]
    return m * len(parts), tuple(com.tolist()), tuple(values.tolist()), matrix_to_quat(vectors)


def matrix_to_quat(r: np.ndarray) -> tuple[float, float, float, float]:
    """(x, y, z, w) of a proper rotation matrix."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * np.sqrt(t + 1.0)
        q = ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4)
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = (s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s)
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * np.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = ((r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s)
    else:
        s = 2.0 * np.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = ((r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4, (r[1, 0] - r[0, 1]) / s)
    return tuple(float(v) for v in q)  # type: ignore[return-value]
