"""What a module does, as compact comparable figures: the firmware agreement test records the
same figures from the profile that were recorded from the ATRON firmware's own code (README.md
beside this file).

A world is run with every hal call observed: joint commands (with the time, the kind and the
argument), packets per physical connector (time and bytes), LED values; at the end each module's
role, event vectors, command table, whether it halted and how many errors it reported.
Sequences are kept as their count and a digest, so a run of two minutes fits on a line.
"""

from __future__ import annotations

import hashlib
from typing import Any

from vm.lattice.world import LatticeWorld

Figures = dict[str, Any]


def digest(items: list[Any]) -> list[Any]:
    return [len(items), hashlib.sha256(repr(items).encode()).hexdigest()[:16]]


class Recorder:
    """Observes every hal of a lattice world (before anything runs)."""

    def __init__(self, world: LatticeWorld) -> None:
        self.world = world
        self.joint: dict[int, list[tuple[float, str, Any]]] = {}
        self.packets: dict[int, dict[int, list[tuple[float, str]]]] = {}
        self.leds: dict[int, list[tuple[float, int]]] = {}
        for mid, hal in world.hals.items():
            self.joint[mid], self.packets[mid], self.leds[mid] = [], {}, []
            for name, kind in (("rotate_continuously", "C"), ("rotate_to", "T"), ("rotate_by", "D"),
                               ("stop_joint", "S")):
                setattr(hal, name, self._joint(mid, kind, getattr(hal, name)))
            hal.send = self._send(mid, hal.send)  # type: ignore[method-assign]
            hal.set_led = self._led(mid, hal.set_led)  # type: ignore[method-assign]

    def _now(self) -> float:
        return round(self.world.now(), 2)

    def _joint(self, mid: int, kind: str, call):  # noqa: ANN001, ANN202 - wraps a hal method
        def observed(*args: Any) -> Any:
            value = args[0] if args else None
            self.joint[mid].append((self._now(), kind, None if value is None else round(float(value), 3)))
            return call(*args)
        return observed

    def _send(self, mid: int, call):  # noqa: ANN001, ANN202
        def observed(channel: int, packet: bytes) -> None:
            self.packets[mid].setdefault(channel, []).append((self._now(), bytes(packet).hex()))
            call(channel, packet)
        return observed

    def _led(self, mid: int, call):  # noqa: ANN001, ANN202
        def observed(value: int) -> None:
            self.leds[mid].append((self._now(), value & 0xFF))
            call(value)
        return observed

    def module(self, mid: int, *, role: int, vectors: list[int], table: list[int], halted: bool,
               errors: int) -> Figures:
        return {"role": role, "vectors": vectors, "commands": digest(table), "joint": digest(self.joint[mid]),
                "packets": {str(ch): digest(p) for ch, p in sorted(self.packets[mid].items())},
                "leds": digest(self.leds[mid]), "halted": halted, "errors": errors}
