"""One module's ``vm.hal.ModuleHal`` in the physics world."""

from __future__ import annotations

from typing import TYPE_CHECKING

from sim import params
from sim.joint import PhysicsJoint

if TYPE_CHECKING:
    from sim.world import PhysicsWorld


class PhysicsHal:
    def __init__(self, world: PhysicsWorld, module_id: int, joint: PhysicsJoint | None) -> None:
        self.world = world
        self.module_id = module_id
        self.joint = joint
        self.led = 0
        self.result: int | None = 0  # the last connector or quarter-turn action's answer (None: under way)
        self._connected = world.structure.connected_channels(module_id)

    def now(self) -> float:
        return self.world.time

    def connected_channels(self) -> frozenset[int]:
        return self._connected

    def send(self, physical_channel: int, packet: bytes) -> None:
        self.world.network.send(self.world.time, self.module_id, physical_channel, packet)

    def proximity(self, sensor: int) -> bool:
        return self.world.sensors.value(self.module_id, sensor)

    def joint_angle_deg(self) -> float:
        return self.joint.angle_deg() if self.joint else 0.0

    def joint_turns(self) -> float:
        return self.joint.turns if self.joint else 0.0

    def is_turning(self) -> bool:
        return self.joint.is_turning() if self.joint else False

    def rotate_continuously(self, speed: int) -> None:
        if self.joint:
            self.joint.rotate_continuously(speed)

    def rotate_to(self, angle_deg: float) -> None:
        if self.joint:
            self.joint.rotate_to(angle_deg)

    def rotate_by(self, delta_deg: float) -> None:
        if self.joint:
            self.joint.rotate_by(delta_deg)

    def stop_joint(self) -> None:
        if self.joint:
            self.joint.stop()

    def set_led(self, value: int) -> None:
        self.led = value

    # ---- structures that change (sim.reshape) ----------------------------------------------
    def connect(self, physical_channel: int) -> None:
        self.result = self.world.shape.act(self.module_id, "connect", physical_channel)

    def disconnect(self, physical_channel: int) -> None:
        self.result = self.world.shape.act(self.module_id, "disconnect", physical_channel)

    def rotate_quarters(self, quarters: int) -> None:
        self.result = self.world.shape.act(self.module_id, "turn", quarters)

    def action_result(self) -> int | None:
        return self.result

    def is_connected(self, physical_channel: int) -> bool:
        return physical_channel in self._connected

    def other_connector_nearby(self, physical_channel: int) -> bool:
        """Latched, or a connector of another module within the latch distance (the firmware's
        isOtherConnectorNearby, as USSR's ATRON answers it)."""
        if physical_channel in self._connected:
            return True
        if not 0 <= physical_channel <= 7 or self.module_id in self.world.stopped:
            return False
        gap = self.world.shape.gap(self.module_id, physical_channel)
        return gap is not None and gap <= params.LATCH_DISTANCE
