"""The interface a world implements for one module (docs/architecture.md rule 4).

The VM sees its world only through this: it never learns its position or orientation except
from packets. A world (``vm.lattice`` without physics, ``sim`` with PyBullet) creates one
``ModuleHal`` per module, gives it to a ``vm.runtime`` module, delivers received packets by
calling the runtime's ``receive(physical_channel, packet)``, and calls its ``step()`` regularly.
"""

from __future__ import annotations

from typing import Protocol


class ModuleHal(Protocol):
    def now(self) -> float:
        """Simulated time in seconds."""
        ...

    def connected_channels(self) -> frozenset[int]:
        """Physical connectors (0..7) that have a neighbour attached."""
        ...

    def send(self, physical_channel: int, packet: bytes) -> None:
        """Send a packet over the IR link of one physical connector (may be lost)."""
        ...

    def proximity(self, sensor: int) -> bool:
        """Whether physical IR sensor ``sensor`` (0..7) sees an object within range."""
        ...

    def joint_angle_deg(self) -> float:
        """Current joint angle in degrees, in -180..180."""
        ...

    def joint_turns(self) -> float:
        """Total rotation of the joint since start, in turns (absolute, never decreasing)."""
        ...

    def is_turning(self) -> bool:
        """Whether the joint is moving towards a target or rotating continuously."""
        ...

    def rotate_continuously(self, speed: int) -> None:
        """Rotate without end: speed > 0 clockwise, < 0 counter-clockwise; |speed| scales the
        configured joint speed (1 = the default)."""
        ...

    def rotate_to(self, angle_deg: float) -> None:
        """Rotate to an absolute joint angle, by the shorter way."""
        ...

    def rotate_by(self, delta_deg: float) -> None:
        """Rotate relative to the current angle."""
        ...

    def stop_joint(self) -> None:
        ...

    def set_led(self, value: int) -> None:
        ...

    # ---- structures that change (docs/simulator.md "Structures that change") ------------------
    # An action is started by one call and answered by ``action_result``: None while the module's
    # last action is under way, then 1 (done) or 0 (failed; the world records why). A module
    # runs one action at a time (its program waits for the answer).

    def connect(self, physical_channel: int) -> None:
        """Latch male connector ``physical_channel`` onto the female connector that faces it."""
        ...

    def disconnect(self, physical_channel: int) -> None:
        """Open the latch of connector ``physical_channel`` (a male one, or one of a same-sex link)."""
        ...

    def rotate_quarters(self, quarters: int) -> None:
        """Turn the joint ``quarters`` quarter turns (> 0: the positive, clockwise, direction),
        carrying everything attached to the turning hemisphere."""
        ...

    def action_result(self) -> int | None:
        """None while the last action runs; then 1 if it succeeded, 0 if it failed."""
        ...

    def is_connected(self, physical_channel: int) -> bool:
        """Whether connector ``physical_channel`` is latched to a neighbour."""
        ...

    def other_connector_nearby(self, physical_channel: int) -> bool:
        """Whether a connector of a module on the adjacent cell faces ``physical_channel``
        (the firmware's isOtherConnectorNearby)."""
        ...
