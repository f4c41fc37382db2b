"""Where the robot's links are now: world positions and rotation matrices, read in one call.

Plain tuples rather than numpy arrays: the vectors are tiny and these run at every sensor and
trajectory sample, where numpy's per-call overhead would cost more than the arithmetic.
"""

from __future__ import annotations

import pybullet as pb

from sim.geometry import Vec3

Matrix = tuple[Vec3, Vec3, Vec3]  # rows
Pose = tuple[Vec3, Matrix]  # a link frame's world position and rotation


def quat_matrix(q: tuple[float, float, float, float]) -> Matrix:
    x, y, z, w = q
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )


def to_world(pose: Pose, v: Vec3) -> Vec3:
    """The point ``v``, given in the link frame of ``pose``, in world coordinates."""
    (px, py, pz), ((a, b, c), (d, e, f), (g, h, i)) = pose
    x, y, z = v
    return (px + (a * x + b * y + c * z), py + (d * x + e * y + f * z), pz + (g * x + h * y + i * z))


def link_poses(body: int, links: set[int], client: int) -> dict[int, Pose]:
    """World position and rotation matrix of each link's frame."""
    order = sorted(links)
    states = pb.getLinkStates(body, order, physicsClientId=client)
    return {link: (state[4], quat_matrix(state[5])) for link, state in zip(order, states, strict=True)}
