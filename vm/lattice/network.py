"""The IR links of a lattice world: packets in flight, seeded loss, corruption and delay."""

from __future__ import annotations

import heapq
import random
from collections.abc import Callable
from dataclasses import dataclass, field

from vm.lattice.structure import Structure
from vm.packets import PACKET_BUDGET


@dataclass
class Counters:
    sent: int = 0  # packets handed to a connected link
    delivered: int = 0
    dropped: int = 0  # lost on a connected link
    corrupted: int = 0  # delivered with one byte changed
    unconnected: int = 0  # sent on a connector with nobody attached (nobody hears them)
    oversize: int = 0  # longer than the 50-byte IR packet limit: not sent, as on the hardware

    def as_dict(self) -> dict[str, int]:
        return dict(self.__dict__)


@dataclass(order=True)
class InFlight:
    due: float
    seq: int
    target: int = field(compare=False)
    physical: int = field(compare=False)
    packet: bytes = field(compare=False)


class Network:
    def __init__(self, structure: Structure, rng: random.Random, *, loss: float = 0.0,
                 corruption: float = 0.0, latency_s: float = 0.01, jitter_s: float = 0.0) -> None:
        for label, p in (("packet_loss", loss), ("packet_corruption", corruption)):
            if not 0.0 <= p <= 1.0:
                raise ValueError(f"{label} must lie in 0..1, got {p}")
        if latency_s < 0 or jitter_s < 0:
            raise ValueError("latency and jitter must not be negative")
        self.structure = structure
        self.rng = rng
        self.loss, self.corruption = loss, corruption
        self.latency_s, self.jitter_s = latency_s, jitter_s
        self.counters = Counters()
        self._queue: list[InFlight] = []
        self._seq = 0
        self._ports: dict[int, dict[int, tuple[int, int]]] = {}
        self.refresh()
        # an observer of every packet on a connected link (a replay recording); off by default:
        # on_send(now, source, target, physical, packet, dropped)
        self.on_send: Callable[[float, int, int, int, bytes, bool], None] | None = None
        # told of every packet over the IR packet limit, which is not sent (a run's report says
        # so): on_oversize(now, source, physical, packet)
        self.on_oversize: Callable[[float, int, int, bytes], None] | None = None

    def refresh(self) -> None:
        """Read the links again (after the structure changed)."""
        self._ports = {mid: self.structure.neighbours(mid) for mid in self.structure.modules}

    def send(self, now: float, source: int, physical: int, packet: bytes) -> None:
        packet = bytes(packet)
        ports = self._ports.get(source)
        peer = ports.get(physical) if ports is not None else None
        if peer is None:
            self.counters.unconnected += 1
            return
        if len(packet) > PACKET_BUDGET:  # the ATRON's IR link does not carry it (docs/vm.md)
            self.counters.oversize += 1
            if self.on_oversize is not None:
                self.on_oversize(now, source, physical, packet)
            return
        self.counters.sent += 1
        if self.loss and self.rng.random() < self.loss:
            self.counters.dropped += 1
            if self.on_send is not None:
                self.on_send(now, source, peer[0], physical, packet, True)
            return
        if self.on_send is not None:
            self.on_send(now, source, peer[0], physical, packet, False)
        if self.corruption and packet and self.rng.random() < self.corruption:
            i = self.rng.randrange(len(packet))
            packet = packet[:i] + bytes([packet[i] ^ (1 << self.rng.randrange(8))]) + packet[i + 1:]
            self.counters.corrupted += 1
        delay = self.latency_s + (self.rng.uniform(0, self.jitter_s) if self.jitter_s else 0.0)
        self._seq += 1
        heapq.heappush(self._queue, InFlight(now + delay, self._seq, peer[0], peer[1], packet))

    def due(self, now: float) -> list[InFlight]:
        """Pop every packet due at or before ``now``, in order of arrival."""
        out = []
        while self._queue and self._queue[0].due <= now + 1e-12:
            out.append(heapq.heappop(self._queue))
        self.counters.delivered += len(out)
        return out

    def in_flight(self) -> int:
        return len(self._queue)
