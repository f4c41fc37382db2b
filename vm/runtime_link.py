"""Acknowledged per-link delivery for the DCD-VM (docs/vm.md).

Every program, command and notify packet a module sends on a physical channel is kept in an
outbox until the neighbour acknowledges it with an ack packet (type 4: the acked id and type and
a CRC-8 of the whole packet as received). Unacknowledged packets are sent again after
``RETRY_INTERVAL`` seconds, the interval doubling up to ``MAX_BACKOFF`` times that (a busy
neighbour with a full program store gets time to free a slot), with a little seeded jitter so that
two neighbours do not stay in step. A program, notify or value packet is sent again for as long as
its neighbour stays attached (none can run twice: programs are remembered for ever, and a notify or
a value is the latest, replacing an older one here), so that at any loss below 100 % every module
gets its code and its neighbours' values, only later; a command, remembered by its receiver for
``COMMAND_MEMORY`` seconds only, is given up after ``MAX_TRIES`` tries (about 18 s). A receiver
acknowledges every copy it accepts, including duplicates (the first ack may have been lost), and
runs a program or command only once (duplicate suppression lives in ``vm.runtime_node``). A
corrupted copy yields a different CRC and is therefore not acknowledged as the original, so the
sender retries. A newer notify on a channel replaces an older one still waiting, so a late retry
can never overwrite a newer role in a neighbour's cache. With loss p per packet, a try fails with
probability 1-(1-p)^2 (packet or ack lost): at p = 10 % that is 0.19, and all 12 tries of a
command fail with probability < 1e-8.

Program packets travel in order on each link: a program packet is held back while an earlier one
on the same channel is still unacknowledged, and released when that one is acknowledged (or
forgotten, its neighbour gone). By induction every module then accepts fragments in the order they
were injected, also under loss and in cyclic structures, so a discovery fragment never overtakes the
fragments it follows.

``acknowledged=False`` is the original firmware (docs/vm.md): every packet is sent once,
nothing is acknowledged or retransmitted, and a lost packet stays lost.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

from vm.hal import ModuleHal
from vm.packets import ACK, COMMAND, NOTIFY, PROGRAM, VALUE, AckPacket, crc8, encode, make_header, seal

RETRY_INTERVAL = 0.25  # seconds
MAX_TRIES = 12
MAX_BACKOFF = 8
MAX_OUTBOX = 48


@dataclass
class Pending:
    channel: int
    packet: bytes
    checksum: int
    due: float
    tries: int = 1
    held: bool = False  # waiting behind an earlier program packet on the same channel


class Link:
    def __init__(self, hal: ModuleHal, rng: random.Random, *, checksum: bool = False,
                 acknowledged: bool = True) -> None:
        self.hal = hal
        self.acknowledged = acknowledged
        self.checksum = checksum
        self.rng = rng
        self.outbox: list[Pending] = []
        self.sent = 0
        self.retransmissions = 0
        self.given_up = 0
        self.overflows = 0

    def send(self, channel: int, packet: bytes) -> None:
        """Send reliably: keep the packet until acknowledged or out of tries."""
        if not self.acknowledged:
            self._transmit(channel, packet)
            return
        if packet[0] == NOTIFY:
            self.outbox = [p for p in self.outbox if not (p.channel == channel and p.packet[0] == NOTIFY)]
        elif packet[0] == VALUE:  # a newer value of a state replaces one not yet acknowledged
            self.outbox = [p for p in self.outbox if not (p.channel == channel and p.packet[0] == VALUE
                                                          and p.packet[7] & 0x7F == packet[7] & 0x7F)]
        if len(self.outbox) >= MAX_OUTBOX:
            self.outbox.pop(0)
            self.overflows += 1
        held = packet[0] == PROGRAM and self._program_in_flight(channel)
        self.outbox.append(Pending(channel, packet, crc8(packet), self._next_due(1), held=held))
        if not held:
            self._transmit(channel, packet)

    def send_ack(self, channel: int, packet: bytes) -> None:
        """Acknowledge a received packet (acks themselves are not acknowledged)."""
        if not self.acknowledged:
            return
        self._transmit(channel, encode(AckPacket(make_header(ACK, packet[1]), packet[0], crc8(packet))))

    def on_ack(self, channel: int, ack: AckPacket) -> None:
        self.outbox = [p for p in self.outbox
                       if not (p.channel == channel and p.checksum == ack.checksum
                               and p.packet[0] == ack.acked_type and p.packet[1] == ack.header.id)]
        self._release(channel)

    def _program_in_flight(self, channel: int) -> bool:
        return any(p.channel == channel and p.packet[0] == PROGRAM and not p.held for p in self.outbox)

    def _release(self, channel: int) -> None:
        """Send the next held program packet on ``channel`` once none is in flight there."""
        if self._program_in_flight(channel):
            return
        for p in self.outbox:
            if p.channel == channel and p.held:
                p.held = False
                p.due = self._next_due(1)
                self._transmit(channel, p.packet)
                return

    def tick(self) -> None:
        """Retransmit what is due; forget what has run out of tries or lost its neighbour."""
        now = self.hal.now()
        connected = self.hal.connected_channels()
        keep: list[Pending] = []
        released: set[int] = set()
        for p in self.outbox:
            if p.channel not in connected:
                continue
            if p.held:
                keep.append(p)
                continue
            if p.due <= now:
                if p.tries >= MAX_TRIES and p.packet[0] == COMMAND:
                    self.given_up += 1
                    released.add(p.channel)
                    continue
                p.tries += 1
                p.due = self._next_due(p.tries)
                self.retransmissions += 1
                self._transmit(p.channel, p.packet)
            keep.append(p)
        self.outbox = keep
        for channel in released | {p.channel for p in keep if p.held}:
            self._release(channel)

    def _next_due(self, tries: int) -> float:
        backoff = min(2 ** (tries - 1), MAX_BACKOFF)
        return self.hal.now() + RETRY_INTERVAL * backoff * (1.0 + 0.5 * self.rng.random())

    def _transmit(self, channel: int, packet: bytes) -> None:
        self.sent += 1
        self.hal.send(channel, seal(packet) if self.checksum else packet)
