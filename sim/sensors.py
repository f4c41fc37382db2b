"""Infrared proximity sensors: a small cone of ray casts from under each connector.

Sensors are sampled at ``params.IR_RATE_HZ``, in one ``rayTestBatch``, and only those the VMs
have asked about (a module polls the sensors its event vectors watch). A sensor sees an object
when any ray of its cone hits an obstacle within range of the module surface.
"""

from __future__ import annotations

import math

import numpy as np
import pybullet as pb

from sim import geometry as g
from sim import params
from sim.poses import link_poses, to_world
from sim.robot import Robot
from vm.lattice.structure import Structure


def cone(direction: g.Vec3, rays: int, half_angle_deg: float) -> np.ndarray:
    """Unit ray directions: the axis, then ``rays - 1`` around the cone's edge."""
    d = np.array(direction, dtype=float)
    helper = np.array((0.0, 0.0, 1.0)) if abs(d[2]) < 0.9 else np.array((1.0, 0.0, 0.0))
    u = np.cross(d, helper)
    u /= np.linalg.norm(u)
    w = np.cross(d, u)
    out = [d]
    a = math.radians(half_angle_deg)
    for i in range(rays - 1):
        phi = 2 * math.pi * i / (rays - 1)
        out.append(math.cos(a) * d + math.sin(a) * (math.cos(phi) * u + math.sin(phi) * w))
    return np.array(out)


class Sensors:
    def __init__(self, structure: Structure, robot: Robot, client: int) -> None:
        self.robot, self.client = robot, client
        self.targets: set[int] = set()  # body ids a sensor can see
        self.watched: set[tuple[int, int]] = set()
        self.values: dict[tuple[int, int], bool] = {}
        self.rising: list[tuple[int, int]] = []  # (module, sensor) that turned on at the last sample
        # (module, sensor) -> (link, sensor origin and the ends of its rays, in the link frame)
        self._rays: dict[tuple[int, int], tuple[int, g.Vec3, list[g.Vec3]]] = {}
        for mid, spec in structure.modules.items():
            mb = robot.modules[mid]
            for k in range(8):
                side = g.physical_side(spec, k)
                direction = g.physical_connector_direction(spec, k)
                out = params.MODULE_RADIUS + params.IR_SENSOR_OFFSET
                origin = np.array(mb.offsets[side]) + np.array(direction) * out
                rays = cone(direction, params.IR_RAYS, params.IR_CONE_HALF_ANGLE_DEG)
                ends = origin + rays * params.IR_RANGE
                self._rays[(mid, k)] = (mb.links[side], tuple(origin.tolist()),
                                        [tuple(end) for end in ends.tolist()])

    def value(self, module: int, sensor: int) -> bool:
        key = (module, sensor)
        self.watched.add(key)
        return self.values.get(key, False)

    def sample(self) -> None:
        """Cast the rays of every watched sensor; record which ones turned on."""
        self.rising = []
        keys = sorted(self.watched)
        if not keys:
            return
        poses = link_poses(self.robot.body, {self._rays[k][0] for k in keys}, self.client)
        starts: list[g.Vec3] = []
        ends: list[g.Vec3] = []
        for key in keys:
            link, origin, tips = self._rays[key]
            pose = poses[link]
            starts += [to_world(pose, origin)] * len(tips)
            ends += [to_world(pose, tip) for tip in tips]
        hits = pb.rayTestBatch(starts, ends, physicsClientId=self.client)
        n = params.IR_RAYS
        for i, key in enumerate(keys):
            seen = any(h[0] in self.targets for h in hits[i * n:(i + 1) * n])
            if seen and not self.values.get(key, False):
                self.rising.append(key)
            self.values[key] = seen
