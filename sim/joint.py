"""The motorised ATRON joint in PyBullet: continuous rotation, rotate-to, hold, turn counting.

Angles follow ``sim.robot``'s convention (positive = clockwise = south hemisphere turning
clockwise seen from the north pole). The motor is a velocity motor limited to the joint torque;
rotate-to is a proportional controller capped at the joint speed, updated every VM tick.

A quarter turn (``turn_quarters``, the structure-changing action) that makes no headway for
``params.JOINT_STALL_S`` has failed, as on the robot when the load is more than the joint's
torque can lift: the joint gives up and holds (``stalled``). The older rotate-to and rotate-by
commands keep trying, as they always did (an axle steering against its wheels' scrub).
After a change of shape (``sim.topology``) the joint is a new PyBullet joint whose zero is the
angle it stood at: ``rebind`` keeps the angle going on from there. A joint whose module closes a
loop of the structure is locked (no PyBullet joint): it cannot turn.
"""

from __future__ import annotations

import math

import pybullet as pb

from sim import params
from vm.lattice.joint import shorter_turn, wrap


class PhysicsJoint:
    def __init__(self, client: int, body: int, joint: int | None) -> None:
        self.client, self.body, self.joint = client, body, joint
        self.offset = 0.0  # rad: the angle at which the PyBullet joint reads 0
        self.stalled = False  # the last quarter turn gave up: the load was too heavy
        self._headway: tuple[float, float] | None = None  # quarter turn: (ticks of no headway, best error)
        self.angle = 0.0  # rad, unwrapped, as measured at the last update
        self.turns = 0.0
        self.velocity = 0.0  # commanded rad/s in continuous mode
        self.target: float | None = None  # rad, unwrapped, in rotate-to mode
        self._command = 0.0

    def measure(self) -> float:
        if self.joint is None:
            return self.angle
        return self.offset + pb.getJointState(self.body, self.joint, physicsClientId=self.client)[0]

    def rebind(self, body: int, joint: int | None) -> None:
        """The same joint in a rebuilt body (``joint`` None: locked in a loop)."""
        self.offset = self.angle
        self.body, self.joint = body, joint
        self._command = math.nan  # the new joint's motor is set at the next update
        if joint is None:
            self.velocity, self.target = 0.0, None

    def update(self, angle: float | None = None) -> None:
        """Read the joint (or take ``angle``, as PyBullet reads it), count its turns and set the
        motor for the mode."""
        angle = self.measure() if angle is None else self.offset + angle
        self.turns += abs(angle - self.angle) / (2 * math.pi)
        self.angle = angle
        if self.joint is None:
            return
        if self.target is not None:
            error = self.target - angle
            if self._headway is not None and self._no_headway(abs(error)):
                self.stalled, self.target, self._headway, error = True, None, None, 0.0
            cap = params.JOINT_SPEED
            command = max(-cap, min(cap, params.JOINT_POSITION_GAIN * error))
        else:
            command = self.velocity
        if command != self._command:
            self._command = command
            pb.setJointMotorControl2(self.body, self.joint, pb.VELOCITY_CONTROL, targetVelocity=command,
                                     force=params.JOINT_MAX_TORQUE, physicsClientId=self.client)

    def _no_headway(self, error: float) -> bool:
        """True once the error has not shrunk by ``params.JOINT_STALL_DEG`` for
        ``params.JOINT_STALL_S`` (counted in updates: one per VM tick)."""
        ticks, best = self._headway  # type: ignore[misc]
        if error < best - math.radians(params.JOINT_STALL_DEG):
            self._headway = (0.0, error)
            return False
        ticks += 1
        self._headway = (ticks, best)
        done = error <= math.radians(params.JOINT_ANGLE_TOLERANCE_DEG)
        return ticks / params.VM_HZ >= params.JOINT_STALL_S and not done

    def angle_deg(self) -> float:
        return wrap(math.degrees(self.angle))

    def is_turning(self) -> bool:
        if self.target is not None:
            return abs(self.target - self.angle) > math.radians(params.JOINT_ANGLE_TOLERANCE_DEG)
        return self.velocity != 0.0

    def rotate_continuously(self, speed: int) -> None:
        self.target, self._headway = None, None
        self.velocity = speed * params.JOINT_SPEED if self.joint is not None else 0.0
        self.update()

    def rotate_by(self, delta_deg: float) -> None:
        self.velocity = 0.0
        self._headway = None
        # a joint locked in a loop does not move, and is not "turning" (as before it had no object)
        self.target = self.angle + math.radians(delta_deg) if self.joint is not None else None
        self.update()

    def turn_quarters(self, quarters: int) -> None:
        """A quarter turn that gives up when it makes no headway (``stalled``)."""
        self.rotate_by(90.0 * quarters)
        self.stalled = False
        self._headway = (0.0, abs(math.radians(90.0 * quarters)))
        if self.joint is None:  # locked in a loop: the turn fails at once
            self.stalled, self.target, self._headway = True, None, None

    def rotate_to(self, angle_deg: float) -> None:
        self.rotate_by(shorter_turn(angle_deg - self.angle_deg()))

    def stop(self) -> None:
        self.velocity = 0.0
        self.target, self._headway = None, None
        self.update()
