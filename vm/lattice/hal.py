"""One module's ``vm.hal.ModuleHal`` in a lattice world: links from the structure, proximity from
obstacle cells, a kinematic joint."""

from __future__ import annotations

from typing import Protocol

from vm.lattice.joint import Joint
from vm.lattice.structure import Structure

Vec = tuple[int, int, int]


class WorldView(Protocol):
    """What a hal needs from its world."""

    structure: Structure
    obstacles: frozenset[Vec]
    sensor_range_steps: int

    def now(self) -> float: ...

    def transmit(self, source: int, physical: int, packet: bytes) -> None: ...


class LatticeHal:
    def __init__(self, world: WorldView, module_id: int, joint_speed_deg_s: float) -> None:
        self.world = world
        self.module_id = module_id
        self.joint = Joint(joint_speed_deg_s)
        self.led = 0
        self._connected = world.structure.connected_channels(module_id)
        spec = world.structure.modules[module_id]
        self._position = spec.position
        self._directions = [world.structure.physical_direction(module_id, p) for p in range(8)]

    def now(self) -> float:
        return self.world.now()

    def connected_channels(self) -> frozenset[int]:
        return self._connected

    def send(self, physical_channel: int, packet: bytes) -> None:
        self.world.transmit(self.module_id, physical_channel, packet)

    def proximity(self, sensor: int) -> bool:
        """An obstacle cell 1..range lattice steps out along the sensor's connector, which is free."""
        if not 0 <= sensor < 8 or sensor in self._connected or not self.world.obstacles:
            return False
        (x, y, z), (dx, dy, dz) = self._position, self._directions[sensor]
        return any((x + k * dx, y + k * dy, z + k * dz) in self.world.obstacles
                   for k in range(1, self.world.sensor_range_steps + 1))

    def joint_angle_deg(self) -> float:
        return self.joint.angle

    def joint_turns(self) -> float:
        return self.joint.turns

    def is_turning(self) -> bool:
        return self.joint.is_turning()

    def rotate_continuously(self, speed: int) -> None:
        self.joint.rotate_continuously(speed)

    def rotate_to(self, angle_deg: float) -> None:
        self.joint.rotate_to(angle_deg)

    def rotate_by(self, delta_deg: float) -> None:
        self.joint.rotate_by(delta_deg)

    def stop_joint(self) -> None:
        self.joint.stop()

    def set_led(self, value: int) -> None:
        self.led = value
