"""Where the robot's links are now: world positions and rotation matrices, read in one call."""

from __future__ import annotations

import numpy as np
import pybullet as pb


def quat_matrix(q: tuple[float, float, float, float]) -> np.ndarray:
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def link_poses(body: int, links: set[int], client: int) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """World position and rotation matrix of each link's frame."""
    order = sorted(links)
    states = pb.getLinkStates(body, order, physicsClientId=client)
    return {link: (np.array(state[4]), quat_matrix(state[5]))
            for link, state in zip(order, states, strict=True)}
