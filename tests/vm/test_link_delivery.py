"""The DCD-VM's acknowledged links (vm/runtime_link.py) at any loss below 100 %: a program, a notify
or a published value is sent again for as long as its neighbour stays attached, so a lost packet
delays the robot but never leaves a module without its code or a value (issue 24: "every run ends
in the target shape at every loss rate below 100 %, only later"). A command, which its receiver
remembers only for 30 s, is given up after MAX_TRIES (about 18 s)."""

from __future__ import annotations

import random

import pytest

from vm.packets import (
    COMMAND,
    NOTIFY,
    PROGRAM,
    VALUE,
    AckPacket,
    CommandPacket,
    NotifyPacket,
    ProgramPacket,
    ValuePacket,
    crc8,
    encode,
    make_header,
)
from vm.runtime_link import MAX_TRIES, Link


class Hal:
    """A module whose every packet is lost: it records what it sends."""

    def __init__(self) -> None:
        self.t = 0.0
        self.attached = {0}
        self.sent: list[tuple[int, bytes]] = []
        self.times: list[tuple[float, int]] = []

    def now(self) -> float:
        return self.t

    def connected_channels(self) -> set[int]:
        return set(self.attached)

    def send(self, channel: int, packet: bytes) -> None:
        self.sent.append((channel, packet))
        self.times.append((self.t, channel))


PACKETS = {
    PROGRAM: encode(ProgramPacket(make_header(PROGRAM, 1), bytes((0x2B, 0x12)))),
    NOTIFY: encode(NotifyPacket(make_header(NOTIFY, 2), 3)),
    VALUE: encode(ValuePacket(make_header(VALUE, 3), 0, False, 12)),
    COMMAND: encode(CommandPacket(make_header(COMMAND, 4), 1, 128, 0)),
}


def _run(link: Link, hal: Hal, seconds: float) -> None:
    while hal.t < seconds:
        hal.t = round(hal.t + 0.05, 2)
        link.tick()


@pytest.mark.parametrize("kind", [PROGRAM, NOTIFY, VALUE])
def test_a_program_notify_or_value_is_sent_again_while_the_neighbour_is_attached(kind: int) -> None:
    hal = Hal()
    link = Link(hal, random.Random(1))  # type: ignore[arg-type]
    link.send(0, PACKETS[kind])
    _run(link, hal, 300.0)
    tries = len(hal.sent)
    assert tries > 3 * MAX_TRIES and link.given_up == 0  # never given up
    times = [t for t, _ in hal.times]
    # the interval grows to at most 8 x 0.25 s (and half of it as jitter), then stays there
    assert max(b - a for a, b in zip(times, times[1:], strict=False)) <= 8 * 0.25 * 1.5 + 0.05
    assert times[-1] > 297.0
    hal.attached = set()  # the neighbour is gone: the packet is forgotten
    _run(link, hal, 310.0)
    assert link.outbox == [] and len(hal.sent) == tries


def test_a_command_is_given_up_after_max_tries() -> None:
    hal = Hal()
    link = Link(hal, random.Random(1))  # type: ignore[arg-type]
    link.send(0, PACKETS[COMMAND])
    _run(link, hal, 300.0)
    assert len(hal.sent) == MAX_TRIES and link.given_up == 1 and link.outbox == []


def test_an_acknowledged_packet_is_not_sent_again() -> None:
    hal = Hal()
    link = Link(hal, random.Random(1))  # type: ignore[arg-type]
    packet = PACKETS[VALUE]
    link.send(0, packet)
    link.on_ack(0, AckPacket(make_header(4, packet[1]), VALUE, crc8(packet)))
    _run(link, hal, 60.0)
    assert len(hal.sent) == 1 and link.outbox == []
