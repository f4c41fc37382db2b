"""Test doubles for vm/: a scripted HAL and a tiny lattice world wiring modules by the navigation
table, with per-module orientation ("mount": the virtual→physical mapping the module will learn),
seeded packet loss and one tick of link delay."""

from __future__ import annotations

import random
from dataclasses import dataclass, field

from vm import navigation as nav
from vm.isa.targets import DEFAULT, Target
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

Vec = tuple[int, int, int]


@dataclass
class FakeHal:
    world: World | None = None
    index: int = 0
    t: float = 0.0
    connected: set[int] = field(default_factory=set)
    sensors: set[int] = field(default_factory=set)
    turns: float = 0.0
    angle: float = 0.0
    turning: bool = False
    led: int | None = None
    sent: list[tuple[int, bytes]] = field(default_factory=list)
    calls: list[tuple[str, float]] = field(default_factory=list)

    def now(self) -> float:
        return self.world.time if self.world else self.t

    def connected_channels(self) -> frozenset[int]:
        return frozenset(self.connected)

    def send(self, physical_channel: int, packet: bytes) -> None:
        self.sent.append((physical_channel, packet))
        if self.world is not None:
            self.world.transmit(self.index, physical_channel, packet)

    def proximity(self, sensor: int) -> bool:
        return sensor in self.sensors

    def joint_angle_deg(self) -> float:
        return self.angle

    def joint_turns(self) -> float:
        return self.turns

    def is_turning(self) -> bool:
        return self.turning

    def rotate_continuously(self, speed: int) -> None:
        self.calls.append(("rotate_continuously", speed))

    def rotate_to(self, angle_deg: float) -> None:
        self.calls.append(("rotate_to", angle_deg))

    def rotate_by(self, delta_deg: float) -> None:
        self.calls.append(("rotate_by", delta_deg))

    def stop_joint(self) -> None:
        self.calls.append(("stop_joint", 0))

    def set_led(self, value: int) -> None:
        self.led = value

    # connector and joint actions: recorded; answered from ``answer`` (None: still under way)
    answer: int | None = 1

    def connect(self, physical_channel: int) -> None:
        self.calls.append(("connect", physical_channel))

    def disconnect(self, physical_channel: int) -> None:
        self.calls.append(("disconnect", physical_channel))

    def rotate_quarters(self, quarters: int) -> None:
        self.calls.append(("rotate_quarters", quarters))

    def action_result(self) -> int | None:
        return self.answer

    def is_connected(self, physical_channel: int) -> bool:
        return physical_channel in self.connected

    def other_connector_nearby(self, physical_channel: int) -> bool:
        return physical_channel in self.connected


@dataclass(frozen=True)
class Placed:
    position: Vec
    axis: int
    mount: tuple[int, ...]  # virtual → physical channel


class World:
    """Modules at lattice positions; every adjacent pair is connected."""

    def __init__(self, placed: list[Placed], roles: RoleTable | None = None, *, loss: float = 0.0,
                 seed: int = 0, dt: float = 0.01, corrupt: float = 0.0, max_delay: int = 0,
                 checksum: bool = False, target: Target = DEFAULT) -> None:
        self.placed = placed
        self.time = 0.0
        self.dt = dt
        self.loss = loss
        self.corrupt = corrupt
        self.max_delay = max_delay  # extra ticks a packet may be held back (reorders packets)
        self.rng = random.Random(seed)
        self.at = {p.position: i for i, p in enumerate(placed)}
        self.hals = [FakeHal(self, i) for i in range(len(placed))]
        self.links: dict[tuple[int, int], tuple[int, int]] = {}
        for i, p in enumerate(placed):
            for v in nav.CHANNELS:
                x, y, z, raxis, rv = nav.receiver(*p.position, p.axis, v)
                j = self.at.get((x, y, z))
                if j is not None:
                    assert placed[j].axis == raxis
                    self.links[(i, p.mount[v])] = (j, placed[j].mount[rv])
                    self.hals[i].connected.add(p.mount[v])
        self.vms = [ModuleRuntime(h, roles or RoleTable(), module_id=i, seed=seed, checksum=checksum,
                                  target=target) for i, h in enumerate(self.hals)]
        self.in_flight: list[tuple[int, int, int, bytes]] = []
        self.ticks = 0
        self.delivered = 0
        self.dropped = 0

    def transmit(self, i: int, ch: int, packet: bytes) -> None:
        target = self.links.get((i, ch))
        if target is None:
            return
        if self.rng.random() < self.loss:
            self.dropped += 1
            return
        if self.rng.random() < self.corrupt:
            damaged = bytearray(packet)
            damaged[self.rng.randrange(len(damaged))] ^= 1 << self.rng.randrange(8)
            packet = bytes(damaged)
        due = self.ticks + 1 + (self.rng.randrange(self.max_delay + 1) if self.max_delay else 0)
        self.in_flight.append((due, *target, packet))

    def tick(self) -> None:
        self.ticks += 1
        now = [f for f in self.in_flight if f[0] <= self.ticks]
        self.in_flight = [f for f in self.in_flight if f[0] > self.ticks]
        for _, j, ch, packet in now:
            self.delivered += 1
            self.vms[j].receive(ch, packet)
        for vm in self.vms:
            vm.step()
        self.time += self.dt

    def run(self, seconds: float) -> None:
        for _ in range(round(seconds / self.dt)):
            self.tick()


def random_structure(n: int, rng: random.Random, *, mounts: bool = True) -> list[Placed]:
    """A random connected structure of n modules grown from the entry at the origin (NS)."""
    placed = [Placed((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY)]
    taken = {(0, 0, 0)}
    while len(placed) < n:
        base = rng.choice(placed)
        x, y, z, axis, _ = nav.receiver(*base.position, base.axis, rng.randrange(8))
        if (x, y, z) in taken:
            continue
        mount = rng.choice(nav.MAPPINGS) if mounts else nav.IDENTITY
        placed.append(Placed((x, y, z), axis, mount))
        taken.add((x, y, z))
    return placed


def line(n: int) -> list[Placed]:
    """A chain along +y: NS, EW, NS, ... (a snake)."""
    out = []
    pos, axis = (0, 0, 0), nav.NORTH_SOUTH
    for _ in range(n):
        out.append(Placed(pos, axis, nav.IDENTITY))
        x, y, z, axis, _ = nav.receiver(*pos, axis, 3 if axis == nav.NORTH_SOUTH else 1)
        pos = (x, y, z)
    return out
