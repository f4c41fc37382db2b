"""Obstacle specifications (``--obstacle``) and their bodies in the physics world."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pybullet as pb

from sim import params


class ObstacleError(ValueError):
    """A malformed obstacle specification (one line)."""


@dataclass(frozen=True)
class Box:
    """An axis-aligned box on the ground: centre (x, y), extent w along x, l along y (metres)."""

    x: float
    y: float
    w: float
    l: float  # noqa: E741
    kind: str = "box"


MAX_OBSTACLE_M = 1000.0


def _finite(text: str) -> float:
    """A finite number of metres within reach of the simulation (ValueError otherwise)."""
    value = float(text)
    if not math.isfinite(value) or abs(value) > MAX_OBSTACLE_M:
        raise ValueError(text)
    return value


def parse_obstacle(text: str) -> list[Box]:
    """``none``, ``wall:D`` (a wall across +y, its face D m ahead of the driver) or ``box:X,Y,W,L``."""
    kind, _, rest = text.strip().partition(":")
    kind = kind.lower()
    try:
        if kind == "none" and not rest:
            return []
        if kind == "wall":
            d = _finite(rest)
            if d <= 0:
                raise ObstacleError(f"--obstacle {text}: the wall distance must be positive")
            t = params.WALL_THICKNESS
            return [Box(0.0, d + t / 2, params.WALL_WIDTH, t, "wall")]
        if kind == "box":
            x, y, w, length = (_finite(v) for v in rest.split(","))
            if w <= 0 or length <= 0:
                raise ObstacleError(f"--obstacle {text}: width and length must be positive")
            return [Box(x, y, w, length)]
    except ValueError as e:
        if isinstance(e, ObstacleError):
            raise
    raise ObstacleError(f"--obstacle {text!r}: expected none, wall:D or box:X,Y,W,L (metres)")


def create_bodies(boxes: list[Box], client: int) -> list[int]:
    ids = []
    for box in boxes:
        h = params.WALL_HEIGHT if box.kind == "wall" else params.BOX_HEIGHT
        half = (box.w / 2, box.l / 2, h / 2)
        col = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=client)
        vis = pb.createVisualShape(pb.GEOM_BOX, halfExtents=half, rgbaColor=(0.7, 0.3, 0.2, 1.0),
                                   physicsClientId=client)
        ids.append(pb.createMultiBody(0.0, col, vis, (box.x, box.y, h / 2), physicsClientId=client))
    return ids
