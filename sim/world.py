"""The PyBullet world: ground, obstacles, one multibody robot, a DCD-VM per module.

Time advances in VM ticks (``params.VM_HZ``); each tick delivers due packets, steps every
module's runtime in id order, updates the joint motors, then runs the physics substeps at
``params.PHYSICS_HZ``. IR sensors are sampled at ``params.IR_RATE_HZ``, the trajectory at
``params.TRAJECTORY_HZ``. Everything random draws from one seeded generator.

The structure (``vm.lattice.structure``) is the one truth about shape; this world moves bodies
and tells it what happened (``sim.reshape``): a latch made within the connectors' tolerance, a
quarter turn that reached its cells, a turn that stalled. It hears every change of the structure
(its ``listeners``) and builds its bodies again at the end of the tick (``sim.topology``).
While nothing changes the robot is one multibody and a tick costs what it always did.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import pybullet as pb

from sim import geometry as g
from sim import params, quiet, reshape
from sim.hal import PhysicsHal
from sim.joint import PhysicsJoint
from sim.obstacles import Box, create_bodies
from sim.poses import link_poses, quat_matrix, to_world
from sim.robot import Robot, build_robot
from sim.sensors import Sensors
from vm.isa.targets import DEFAULT, Target
from vm.lattice.network import Network
from vm.lattice.structure import Structure
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_firmware import make_runtime


@dataclass
class Tracking:
    trajectory: list[list[float]] = field(default_factory=list)  # [t, x, y, heading_deg]
    detections: list[dict[str, object]] = field(default_factory=list)
    min_distance: float | None = None
    collided: bool = False


class PhysicsWorld:
    def __init__(self, structure: Structure, *, obstacles: list[Box] | None = None, seed: int = 0,
                 packet_loss: float = 0.0, gui: bool = False, visuals: bool = False,
                 changes: list[Any] | None = None) -> None:
        self.structure = structure
        self.time = 0.0
        self.steps = 0
        self.client = quiet.connect(pb.GUI if gui else pb.DIRECT)
        if self.client < 0:
            raise RuntimeError("PyBullet could not open a window (no display?)")
        c = self.client
        pb.setGravity(0, 0, params.GRAVITY, physicsClientId=c)
        pb.setTimeStep(1.0 / params.PHYSICS_HZ, physicsClientId=c)
        pb.setPhysicsEngineParameter(numSolverIterations=params.SOLVER_ITERATIONS, physicsClientId=c)
        plane = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=c)
        self.ground = pb.createMultiBody(0.0, plane, -1, (0, 0, 0), physicsClientId=c)
        pb.changeDynamics(self.ground, -1, lateralFriction=params.GROUND_FRICTION, physicsClientId=c)
        self.boxes = list(obstacles or [])
        self.obstacle_ids = create_bodies(self.boxes, c)
        self.visuals = visuals or gui
        self.robot: Robot = build_robot(structure, c, visuals=self.visuals)
        self.rng = random.Random(seed)
        self.network = Network(structure, self.rng, loss=packet_loss, latency_s=params.IR_LATENCY_S)
        # every module's joint, locked ones too (a module whose joint closes a loop cannot turn)
        self.joints = {mid: PhysicsJoint(c, self.robot.body, mb.joint)
                       for mid, mb in self.robot.modules.items()}
        self.hals = {mid: PhysicsHal(self, mid, self.joints[mid]) for mid in sorted(structure.modules)}
        self.runtimes: dict[int, ModuleRuntime] = {}
        self.tracking = Tracking()
        self.on_detection: Callable[[int, int], None] | None = None
        # the story of the shape: (time, module, kind, detail) of each change, failed action, split
        self.events: list[tuple[float, int, str, dict[str, object]]] = []
        self.on_change: Callable[[float, int, str, dict[str, object]], None] | None = None
        self.stopped: set[int] = set()  # modules taken away or stopped for good: not stepped
        # module id -> its runtime's on_event, for a module attached from outside (sim.run)
        self.make_recorder: Callable[[int], Any] | None = None
        self.shape = reshape.Shape(self)
        # outside changes (vm.lattice.outside.OutsideChange), by time, applied at their VM tick
        self.outside = sorted(changes or [], key=lambda c: c.t)
        self._vm_every = max(1, round(params.PHYSICS_HZ / params.VM_HZ))
        self._ir_every = max(1, round(params.PHYSICS_HZ / params.IR_RATE_HZ))
        self._track_every = max(1, round(params.PHYSICS_HZ / params.TRAJECTORY_HZ))
        self._dt = 1.0 / params.PHYSICS_HZ
        self._runtime_args: tuple[RoleTable, int, Target] | None = None
        self.index_robot()

    def index_robot(self) -> None:
        """What the per-tick code reads of the robot's bodies (again after a change of shape)."""
        robot, c = self.robot, self.client
        self.sensors = Sensors(robot, c, getattr(self, "sensors", None))
        self.sensors.targets = set(self.obstacle_ids) | ({self.ground} if params.IR_SEES_GROUND else set())
        # each module's centre: (body, link of its PLUS hemisphere, centre in that link's frame)
        self._centres = {mid: (mb.body, mb.links[g.PLUS], mb.offsets[g.PLUS])
                         for mid, mb in robot.modules.items() }
        self._centre_links = {body: {link for b, link, _ in self._centres.values() if b == body}
                              for body in robot.bodies}
        groups: dict[int, list[PhysicsJoint]] = {}
        for mid, joint in self.joints.items():
            if joint.joint is not None and mid in robot.modules:
                groups.setdefault(joint.body, []).append(joint)
        self._joint_groups = [(body, js, [j.joint for j in js]) for body, js in groups.items()]

    def close(self) -> None:
        if pb.isConnected(self.client):
            pb.disconnect(self.client)

    # --- VMs -------------------------------------------------------------------------------
    def add_runtimes(self, roles: RoleTable, seed: int, target: Target = DEFAULT) -> dict[int, ModuleRuntime]:
        self._runtime_args = (roles, seed, target)
        for mid in self.hals:
            self.add_runtime(mid)
        return self.runtimes

    def add_runtime(self, mid: int) -> None:
        if self._runtime_args is not None:
            roles, seed, target = self._runtime_args
            self.runtimes[mid] = make_runtime(self.hals[mid], roles, module_id=mid, seed=seed, target=target)
            if self.make_recorder is not None:
                self.runtimes[mid].on_event = self.make_recorder(mid)

    def vm_tick(self) -> None:
        stopped = self.stopped
        for packet in self.network.due(self.time):
            runtime = self.runtimes.get(packet.target)
            if runtime is not None and packet.target not in stopped:
                runtime.receive(packet.physical, packet.packet)
        for runtime in self.runtimes.values():  # a stopped module's runtime is halted
            if runtime.needs_step():
                runtime.step()
        self.update_joints()
        while self.outside and self.outside[0].t <= self.time + 1e-9:
            self.shape.apply_outside(self.outside.pop(0))
        if self.shape.busy:
            self.shape.tick()

    def update_joints(self) -> None:
        for body, joints, indices in self._joint_groups:
            states = pb.getJointStates(body, indices, physicsClientId=self.client)
            for joint, state in zip(joints, states, strict=True):
                joint.update(state[0])

    # --- time ------------------------------------------------------------------------------
    def advance(self, duration: float) -> None:
        """Run VM ticks and physics for ``duration`` simulated seconds."""
        end = self.steps + round(duration * params.PHYSICS_HZ)
        if self.steps == 0:
            self.track()
        every = (self._vm_every, self._ir_every, self._track_every)
        step, client = pb.stepSimulation, self.client
        while self.steps < end:
            if self.steps % self._vm_every == 0:
                self.vm_tick()
            # physics alone up to the next step that has a VM tick, a sensor or a trajectory sample
            n = min(end - self.steps, *(k - self.steps % k for k in every))
            for _ in range(n):
                step(physicsClientId=client)
            self.steps += n
            self.time = self.steps * self._dt
            if self.steps % self._ir_every == 0:
                self.sense()
            if self.steps % self._track_every == 0:
                self.track()

    def sense(self) -> None:
        self.sensors.sample()
        for mid, k in self.sensors.rising:
            self.tracking.detections.append({"t": round(self.time, 3), "module": mid, "sensor": k})
            if self.on_detection:
                self.on_detection(mid, k)

    # --- observation -----------------------------------------------------------------------
    def module_centres(self) -> dict[int, g.Vec3]:
        poses = {body: link_poses(body, links, self.client) for body, links in self._centre_links.items()}
        return {mid: to_world(poses[body][link], offset)
                for mid, (body, link, offset) in self._centres.items()}

    def heading_deg(self) -> float:
        """Heading of the entry module: 0 = +y, positive counter-clockwise seen from above."""
        mb = self.robot.modules[self.structure.entry]
        m = quat_matrix(pb.getLinkState(mb.body, mb.links[g.PLUS], physicsClientId=self.client)[5])
        if g.PLUS in mb.frames:  # the hemisphere turned in its link (a rebuilt body)
            m = tuple(tuple(sum(m[i][k] * mb.frames[g.PLUS][k][j] for k in range(3)) for j in range(3))
                      for i in range(3))  # type: ignore[assignment]
        return math.degrees(math.atan2(-m[0][1], m[1][1]))  # the hemisphere's +y axis: m's middle column

    def centre(self) -> tuple[float, float]:
        """Mean centre of the modules of the entry module's part (not of parts cut off)."""
        main = self.robot.body
        centres = [c for mid, c in self.module_centres().items() if self._centres[mid][0] == main]
        return sum(c[0] for c in centres) / len(centres), sum(c[1] for c in centres) / len(centres)

    def track(self) -> None:
        x, y = self.centre()
        self.tracking.trajectory.append([round(self.time, 3), round(x, 4), round(y, 4),
                                         round(self.heading_deg(), 2)])
        for obstacle in self.obstacle_ids:
            points = [p for body in self.robot.bodies
                      for p in pb.getClosestPoints(body, obstacle, 1.0, physicsClientId=self.client)]
            if not points:
                continue
            d = min(p[8] for p in points)
            t = self.tracking
            t.min_distance = d if t.min_distance is None else min(t.min_distance, d)
            if d < params.COLLISION_MARGIN:
                t.collided = True

