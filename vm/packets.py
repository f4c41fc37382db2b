"""DCD-VM packets (docs/vm.md): a 7-byte header ``type, id, x, y, z, r, vch`` and a body.

Types 1 program (body: the fragment), 2 command (body: role, command, argument), 3 notify
(body: role). This VM adds type 4 **ack** (body: acked type, CRC-8 of the acked packet; the
header's id is the acked packet's id and x y z r vch are 0) for its acknowledged per-link
delivery (see ``vm.runtime_link``). ``x y z`` and the command argument are signed bytes.
``decode`` never raises: garbage gives a ``PacketError``.

Optional link checksum: ``seal`` appends a CRC-8 of the packet, ``unseal`` checks and strips it
(None when corrupted). Used only when a world turns it on for all modules
(``ModuleRuntime(..., checksum=True)``), e.g. when it corrupts packets; it costs one byte of
the 50-byte budget.
"""

from __future__ import annotations

from dataclasses import dataclass

from vm.isa.opcodes import signed_byte
from vm.navigation import AXES

PROGRAM = 1
COMMAND = 2
NOTIFY = 3
ACK = 4
VALUE = 5
TYPE_NAMES = {PROGRAM: "program", COMMAND: "command", NOTIFY: "notify", ACK: "ack", VALUE: "value"}
VALUE_PARENT = 0x80  # a value packet's flag: the receiver is the sender's parent in the tree
HEADER_SIZE = 7
PACKET_BUDGET = 50  # bytes; the hardware IR link became unreliable above this (docs/vm.md)


@dataclass(frozen=True, slots=True)
class Header:
    type: int
    id: int
    x: int
    y: int
    z: int
    r: int
    vch: int


@dataclass(frozen=True, slots=True)
class ProgramPacket:
    header: Header
    code: bytes


@dataclass(frozen=True, slots=True)
class CommandPacket:
    header: Header
    role: int
    command: int
    argument: int


@dataclass(frozen=True, slots=True)
class NotifyPacket:
    header: Header
    role: int


@dataclass(frozen=True, slots=True)
class AckPacket:
    header: Header
    acked_type: int
    checksum: int


@dataclass(frozen=True, slots=True)
class ValuePacket:
    """A published state's new value (this project's type 5): body ``index | parent flag, value``."""

    header: Header
    index: int  # the published state, 0..7
    to_parent: bool  # the receiver is the sender's parent in the structure's tree
    value: int


@dataclass(frozen=True, slots=True)
class PacketError:
    message: str


Packet = ProgramPacket | CommandPacket | NotifyPacket | AckPacket | ValuePacket


def crc8(data: bytes) -> int:
    """CRC-8 (polynomial 0x07), identifies a packet in acks."""
    crc = 0
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def header_bytes(h: Header) -> bytes:
    return bytes(v & 0xFF for v in (h.type, h.id, h.x, h.y, h.z, h.r, h.vch))


def encode(p: Packet) -> bytes:
    h = header_bytes(p.header)
    if isinstance(p, ProgramPacket):
        return h + bytes(p.code)
    if isinstance(p, CommandPacket):
        return h + bytes((p.role & 0xFF, p.command & 0xFF, p.argument & 0xFF))
    if isinstance(p, NotifyPacket):
        return h + bytes((p.role & 0xFF,))
    if isinstance(p, ValuePacket):
        return h + bytes(((p.index & 0x7F) | (VALUE_PARENT if p.to_parent else 0), p.value & 0xFF))
    return h + bytes((p.acked_type & 0xFF, p.checksum & 0xFF))


def make_header(type_: int, id_: int, x: int = 0, y: int = 0, z: int = 0, r: int = 0,
                vch: int = 0) -> Header:
    return Header(type_, id_ & 0xFF, signed_byte(x), signed_byte(y), signed_byte(z), r, vch)


def decode(data: bytes) -> Packet | PacketError:
    """Decode one packet; malformed input gives a PacketError (never raises)."""
    if isinstance(data, int):  # bytes(n) would make n zero bytes
        return PacketError("not bytes")
    try:
        data = bytes(data)
    except (TypeError, ValueError):
        return PacketError("not bytes")
    if len(data) < HEADER_SIZE:
        return PacketError(f"packet of {len(data)} bytes is shorter than the 7-byte header")
    t, pid, x, y, z, r, vch = data[:HEADER_SIZE]
    body = data[HEADER_SIZE:]
    if t not in TYPE_NAMES:
        return PacketError(f"unknown packet type {t}")
    if t != ACK and (r not in AXES or vch > 7):
        return PacketError(f"bad header: axis {r}, virtual channel {vch}")
    h = Header(t, pid, signed_byte(x), signed_byte(y), signed_byte(z), r, vch)
    if t == PROGRAM:
        if not body:
            return PacketError("program packet without program bytes")
        return ProgramPacket(h, body)
    if t == COMMAND:
        if len(body) != 3:
            return PacketError(f"command packet body of {len(body)} bytes, expected 3")
        return CommandPacket(h, body[0], body[1], signed_byte(body[2]))
    if t == NOTIFY:
        if len(body) != 1:
            return PacketError(f"notify packet body of {len(body)} bytes, expected 1")
        return NotifyPacket(h, body[0])
    if t == VALUE:
        if len(body) != 2 or body[0] & 0x7F >= 8:
            return PacketError("value packet body must be 2 bytes: a published state 0..7 and its value")
        return ValuePacket(h, body[0] & 0x7F, bool(body[0] & VALUE_PARENT), signed_byte(body[1]))
    if len(body) != 2:
        return PacketError(f"ack packet body of {len(body)} bytes, expected 2")
    return AckPacket(h, body[0], body[1])


def seal(packet: bytes) -> bytes:
    return packet + bytes((crc8(packet),))


def unseal(data: bytes) -> bytes | None:
    if len(data) < 2 or crc8(data[:-1]) != data[-1]:
        return None
    return data[:-1]
