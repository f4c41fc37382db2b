"""The PyBullet world: ground, obstacles, one multibody robot, a DCD-VM per module.

Time advances in VM ticks (``params.VM_HZ``); each tick delivers due packets, steps every
module's runtime in id order, updates the joint motors, then runs the physics substeps at
``params.PHYSICS_HZ``. IR sensors are sampled at ``params.IR_RATE_HZ``, the trajectory at
``params.TRAJECTORY_HZ``. Everything random draws from one seeded generator.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from dataclasses import dataclass, field

import pybullet as pb

from sim import geometry as g
from sim import params, quiet
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
                 packet_loss: float = 0.0, gui: bool = False, visuals: bool = False) -> None:
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
        self.robot: Robot = build_robot(structure, c, visuals=visuals or gui)
        self.sensors = Sensors(structure, self.robot, c)
        self.sensors.targets = set(self.obstacle_ids) | ({self.ground} if params.IR_SEES_GROUND else set())
        self.rng = random.Random(seed)
        self.network = Network(structure, self.rng, loss=packet_loss, latency_s=params.IR_LATENCY_S)
        self.joints = {mid: PhysicsJoint(c, self.robot.body, mb.joint)
                       for mid, mb in self.robot.modules.items() if mb.joint is not None}
        self._joint_list = list(self.joints.values())
        self._joint_indices = [j.joint for j in self._joint_list]
        self.hals = {mid: PhysicsHal(self, mid, self.joints.get(mid)) for mid in sorted(structure.modules)}
        self.runtimes: dict[int, ModuleRuntime] = {}
        self.tracking = Tracking()
        self.on_detection: Callable[[int, int], None] | None = None
        self._vm_every = max(1, round(params.PHYSICS_HZ / params.VM_HZ))
        self._ir_every = max(1, round(params.PHYSICS_HZ / params.IR_RATE_HZ))
        self._track_every = max(1, round(params.PHYSICS_HZ / params.TRAJECTORY_HZ))
        self._dt = 1.0 / params.PHYSICS_HZ
        # each module's centre: (link of its PLUS hemisphere, centre in that link's frame)
        self._centres = {mid: (mb.links[g.PLUS], mb.offsets[g.PLUS])
                         for mid, mb in self.robot.modules.items()}
        self._centre_links = {link for link, _ in self._centres.values()}

    def close(self) -> None:
        if pb.isConnected(self.client):
            pb.disconnect(self.client)

    # --- VMs -------------------------------------------------------------------------------
    def add_runtimes(self, roles: RoleTable, seed: int, target: Target = DEFAULT) -> dict[int, ModuleRuntime]:
        for mid, hal in self.hals.items():
            self.runtimes[mid] = make_runtime(hal, roles, module_id=mid, seed=seed, target=target)
        return self.runtimes

    def vm_tick(self) -> None:
        for packet in self.network.due(self.time):
            runtime = self.runtimes.get(packet.target)
            if runtime is not None:
                runtime.receive(packet.physical, packet.packet)
        for runtime in self.runtimes.values():
            if runtime.needs_step():
                runtime.step()
        self.update_joints()

    def update_joints(self) -> None:
        if not self._joint_list:
            return
        states = pb.getJointStates(self.robot.body, self._joint_indices, physicsClientId=self.client)
        for joint, state in zip(self._joint_list, states, strict=True):
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
        poses = link_poses(self.robot.body, self._centre_links, self.client)
        return {mid: to_world(poses[link], offset) for mid, (link, offset) in self._centres.items()}

    def heading_deg(self) -> float:
        """Heading of the entry module: 0 = +y, positive counter-clockwise seen from above."""
        link = self._centres[self.structure.entry][0]
        m = quat_matrix(pb.getLinkState(self.robot.body, link, physicsClientId=self.client)[5])
        return math.degrees(math.atan2(-m[0][1], m[1][1]))  # the link's +y axis: m's middle column

    def centre(self) -> tuple[float, float]:
        centres = self.module_centres().values()
        return sum(c[0] for c in centres) / len(centres), sum(c[1] for c in centres) / len(centres)

    def track(self) -> None:
        x, y = self.centre()
        self.tracking.trajectory.append([round(self.time, 3), round(x, 4), round(y, 4),
                                         round(self.heading_deg(), 2)])
        for obstacle in self.obstacle_ids:
            points = pb.getClosestPoints(self.robot.body, obstacle, 1.0, physicsClientId=self.client)
            if not points:
                continue
            d = min(p[8] for p in points)
            t = self.tracking
            t.min_distance = d if t.min_distance is None else min(t.min_distance, d)
            if d < params.COLLISION_MARGIN:
                t.collided = True

