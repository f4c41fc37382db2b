"""One module's ``vm.hal.ModuleHal`` in a lattice world: links from the structure, proximity from
obstacle cells, a kinematic joint; connector and joint actions go to the world, which changes the
structure (``refresh`` is called after every change)."""

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

    def act(self, module_id: int, kind: str, arg: int) -> int | None: ...

    def legacy_motion(self, module_id: int) -> None: ...

    def watches(self, module_id: int, both_sides: bool) -> bool: ...


class LatticeHal:
    def __init__(self, world: WorldView, module_id: int, joint_speed_deg_s: float) -> None:
        self.world = world
        self.module_id = module_id
        self.joint = Joint(joint_speed_deg_s)
        self.led = 0
        self.result: int | None = 0  # the last action's answer (None while it runs)
        self.refresh()

    def refresh(self) -> None:
        """Read this module's links, cell and connector directions from the structure again."""
        structure, mid = self.world.structure, self.module_id
        if mid not in structure.modules:  # taken away: nothing attached, nothing seen
            self._connected = frozenset()
            self.watch = False
            return
        self._connected = structure.connected_channels(mid)
        # the world hears of this module's older joint commands only while they may matter: a
        # quarter turn under way, or a joint holding modules on both sides (not yet reported)
        both = any(c < 4 for c in self._connected) and any(c >= 4 for c in self._connected)
        self.watch = self.world.watches(mid, both)
        self._position = structure.modules[mid].position
        self._directions = [structure.physical_direction(mid, p) for p in range(8)]

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
        if self.watch:
            self.world.legacy_motion(self.module_id)

    def rotate_to(self, angle_deg: float) -> None:
        self.joint.rotate_to(angle_deg)
        if self.watch:
            self.world.legacy_motion(self.module_id)

    def rotate_by(self, delta_deg: float) -> None:
        self.joint.rotate_by(delta_deg)
        if self.watch:
            self.world.legacy_motion(self.module_id)

    def stop_joint(self) -> None:
        self.joint.stop()

    def set_led(self, value: int) -> None:
        self.led = value

    # ---- structures that change ------------------------------------------------------------
    def connect(self, physical_channel: int) -> None:
        self.result = self.world.act(self.module_id, "connect", physical_channel)

    def disconnect(self, physical_channel: int) -> None:
        self.result = self.world.act(self.module_id, "disconnect", physical_channel)

    def rotate_quarters(self, quarters: int) -> None:
        self.result = self.world.act(self.module_id, "turn", quarters)

    def action_result(self) -> int | None:
        return self.result

    def is_connected(self, physical_channel: int) -> bool:
        return physical_channel in self._connected

    def other_connector_nearby(self, physical_channel: int) -> bool:
        structure = self.world.structure
        return self.module_id in structure.modules and 0 <= physical_channel <= 7 and \
            structure.facing(self.module_id, physical_channel) is not None
