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
from sim.frames import connector_direction
from sim.poses import link_poses, to_world
from sim.robot import Robot


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
    """The sensors of ``robot``'s modules (each as created: ``robot.specs``); ``previous``, the
    sensors of the same modules before a change of shape, passes on what was watched and seen."""

    def __init__(self, robot: Robot, client: int, previous: Sensors | None = None) -> None:
        self.robot, self.client = robot, client
        self.targets: set[int] = set()  # body ids a sensor can see
        self.watched: set[tuple[int, int]] = set(previous.watched) if previous else set()
        self.values: dict[tuple[int, int], bool] = dict(previous.values) if previous else {}
        self.rising: list[tuple[int, int]] = []  # (module, sensor) that turned on at the last sample
        # (module, sensor) -> (link, sensor origin and the ends of its rays, in the link frame)
        self._rays: dict[tuple[int, int], tuple[int, g.Vec3, list[g.Vec3]]] = {}
        self._body: dict[tuple[int, int], int] = {}  # (module, sensor) -> its multibody
        for mid, mb in robot.modules.items():
            spec = robot.specs[mid]
            for k in range(8):
                side = g.physical_side(spec, k)
                direction = np.array(connector_direction(spec, k))
                if side in mb.frames:  # the hemisphere sits turned in its link
                    direction = np.array(mb.frames[side]) @ direction
                out = params.MODULE_RADIUS + params.IR_SENSOR_OFFSET
                origin = np.array(mb.offsets[side]) + direction * out
                rays = cone(tuple(direction.tolist()), params.IR_RAYS, params.IR_CONE_HALF_ANGLE_DEG)
                ends = origin + rays * params.IR_RANGE
                self._rays[(mid, k)] = (mb.links[side], tuple(origin.tolist()),
                                        [tuple(end) for end in ends.tolist()])
                self._body[(mid, k)] = mb.body

    def value(self, module: int, sensor: int) -> bool:
        key = (module, sensor)
        self.watched.add(key)
        return self.values.get(key, False)

    def sample(self) -> None:
        """Cast the rays of every watched sensor; record which ones turned on."""
        self.rising = []
        keys = [k for k in sorted(self.watched) if k in self._rays]
        if not keys:
            return
        body = self.robot.body
        if len(self.robot.bodies) == 1:
            poses = {body: link_poses(body, {self._rays[k][0] for k in keys}, self.client)}
        else:
            poses = {b: link_poses(b, {self._rays[k][0] for k in keys if self._body[k] == b}, self.client)
                     for b in {self._body[k] for k in keys}}
        starts: list[g.Vec3] = []
        ends: list[g.Vec3] = []
        for key in keys:
            link, origin, tips = self._rays[key]
            pose = poses[self._body[key]][link]
            starts += [to_world(pose, origin)] * len(tips)
            ends += [to_world(pose, tip) for tip in tips]
        hits = pb.rayTestBatch(starts, ends, physicsClientId=self.client)
        n = params.IR_RAYS
        for i, key in enumerate(keys):
            seen = any(h[0] in self.targets for h in hits[i * n:(i + 1) * n])
            if seen and not self.values.get(key, False):
                self.rising.append(key)
            self.values[key] = seen
