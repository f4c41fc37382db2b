"""A kinematic model of the ATRON joint: rotations take time, turns accumulate.

Positive speed is clockwise and increases the angle. ``speed_deg_s`` is the joint speed at
speed 1 (default one turn in 6 s); continuous rotation at speed v runs |v| times as fast.
"""

from __future__ import annotations


def wrap(angle: float) -> float:
    """Angle in -180..180 (180 maps to -180)."""
    return (angle + 180.0) % 360.0 - 180.0


def shorter_turn(delta_deg: float) -> float:
    """The rotation that goes ``delta_deg`` the shorter way; exactly half a turn goes clockwise."""
    delta = wrap(delta_deg)
    return 180.0 if delta == -180.0 else delta


class Joint:
    def __init__(self, speed_deg_s: float) -> None:
        if speed_deg_s <= 0:
            raise ValueError("joint speed must be positive")
        self.speed_deg_s = speed_deg_s
        self.angle = 0.0
        self.turns = 0.0
        self._velocity = 0.0  # deg/s while rotating continuously
        self._remaining: float | None = None  # deg left to a target, signed

    def is_turning(self) -> bool:
        return self._velocity != 0.0 or self._remaining is not None

    def rotate_continuously(self, speed: int) -> None:
        self._remaining = None
        self._velocity = speed * self.speed_deg_s

    def rotate_by(self, delta_deg: float) -> None:
        self._velocity = 0.0
        self._remaining = float(delta_deg) if delta_deg else None

    def rotate_to(self, angle_deg: float) -> None:
        self.rotate_by(shorter_turn(angle_deg - self.angle))

    def stop(self) -> None:
        self._velocity = 0.0
        self._remaining = None

    def advance(self, dt: float) -> None:
        if self._remaining is not None:
            step = min(abs(self._remaining), self.speed_deg_s * dt)
            move = step if self._remaining > 0 else -step
            self._remaining -= move
            if abs(self._remaining) < 1e-9:
                self._remaining = None
        else:
            move = self._velocity * dt
        self.angle = wrap(self.angle + move)
        self.turns += abs(move) / 360.0
