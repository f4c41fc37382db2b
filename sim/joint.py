"""The motorised ATRON joint in PyBullet: continuous rotation, rotate-to, hold, turn counting.

Angles follow ``sim.robot``'s convention (positive = clockwise = south hemisphere turning
clockwise seen from the north pole). The motor is a velocity motor limited to the joint torque;
rotate-to is a proportional controller capped at the joint speed, updated every VM tick.
"""

from __future__ import annotations

import math

import pybullet as pb

from sim import params
from vm.lattice.joint import shorter_turn, wrap


class PhysicsJoint:
    def __init__(self, client: int, body: int, joint: int) -> None:
        self.client, self.body, self.joint = client, body, joint
        self.angle = 0.0  # rad, unwrapped, as measured at the last update
        self.turns = 0.0
        self.velocity = 0.0  # commanded rad/s in continuous mode
        self.target: float | None = None  # rad, unwrapped, in rotate-to mode
        self._command = 0.0

    def measure(self) -> float:
        return pb.getJointState(self.body, self.joint, physicsClientId=self.client)[0]

    def update(self, angle: float | None = None) -> None:
        """Read the joint (or take ``angle``), count its turns and set the motor for the mode."""
        angle = self.measure() if angle is None else angle
        self.turns += abs(angle - self.angle) / (2 * math.pi)
        self.angle = angle
        if self.target is not None:
            error = self.target - angle
            cap = params.JOINT_SPEED
            command = max(-cap, min(cap, params.JOINT_POSITION_GAIN * error))
        else:
            command = self.velocity
        if command != self._command:
            self._command = command
            pb.setJointMotorControl2(self.body, self.joint, pb.VELOCITY_CONTROL, targetVelocity=command,
                                     force=params.JOINT_MAX_TORQUE, physicsClientId=self.client)

    def angle_deg(self) -> float:
        return wrap(math.degrees(self.angle))

    def is_turning(self) -> bool:
        if self.target is not None:
            return abs(self.target - self.angle) > math.radians(params.JOINT_ANGLE_TOLERANCE_DEG)
        return self.velocity != 0.0

    def rotate_continuously(self, speed: int) -> None:
        self.target = None
        self.velocity = speed * params.JOINT_SPEED
        self.update()

    def rotate_by(self, delta_deg: float) -> None:
        self.velocity = 0.0
        self.target = self.angle + math.radians(delta_deg)
        self.update()

    def rotate_to(self, angle_deg: float) -> None:
        self.rotate_by(shorter_turn(angle_deg - self.angle_deg()))

    def stop(self) -> None:
        self.velocity = 0.0
        self.target = None
        self.update()
