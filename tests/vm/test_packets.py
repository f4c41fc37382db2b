"""Packet encoding (docs/vm.md) and the ack packet this VM adds."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from vm import packets as pk

coords = st.integers(-128, 127)
axes = st.sampled_from([1, 2, 3])
headers = st.builds(pk.Header, st.just(0), st.integers(0, 255), coords, coords, coords, axes,
                    st.integers(0, 7))


def _with_type(h: pk.Header, t: int) -> pk.Header:
    return pk.Header(t, h.id, h.x, h.y, h.z, h.r, h.vch)


@given(headers, st.binary(min_size=1, max_size=43))
def test_program_round_trip(h: pk.Header, code: bytes) -> None:
    p = pk.ProgramPacket(_with_type(h, pk.PROGRAM), code)
    raw = pk.encode(p)
    assert len(raw) == 7 + len(code)
    assert pk.decode(raw) == p


@given(headers, st.integers(0, 255), st.integers(0, 255), st.integers(-128, 127))
def test_command_round_trip(h: pk.Header, role: int, command: int, arg: int) -> None:
    p = pk.CommandPacket(_with_type(h, pk.COMMAND), role, command, arg)
    assert pk.decode(pk.encode(p)) == p


@given(headers, st.integers(0, 255))
def test_notify_round_trip(h: pk.Header, role: int) -> None:
    p = pk.NotifyPacket(_with_type(h, pk.NOTIFY), role)
    assert pk.decode(pk.encode(p)) == p


def test_ack_round_trip() -> None:
    p = pk.AckPacket(pk.make_header(pk.ACK, 7), pk.PROGRAM, 0x5A)
    assert pk.decode(pk.encode(p)) == p


def test_layout_is_the_spec_layout() -> None:
    raw = pk.encode(pk.CommandPacket(pk.make_header(pk.COMMAND, 9, -1, 1, 0, 1, 3), 4, 1, -2))
    assert raw == bytes([2, 9, 255, 1, 0, 1, 3, 4, 1, 254])


@given(st.binary(max_size=60))
def test_garbage_never_raises(raw: bytes) -> None:
    result = pk.decode(raw)
    assert isinstance(result, pk.PacketError | pk.ProgramPacket | pk.CommandPacket | pk.NotifyPacket
                      | pk.AckPacket)


def test_errors() -> None:
    assert isinstance(pk.decode(b"\x01\x00"), pk.PacketError)
    assert isinstance(pk.decode(bytes([9, 0, 0, 0, 0, 2, 0])), pk.PacketError)
    assert isinstance(pk.decode(bytes([1, 0, 0, 0, 0, 2, 0])), pk.PacketError)  # no program
    assert isinstance(pk.decode(bytes([2, 0, 0, 0, 0, 2, 0, 1])), pk.PacketError)
    assert isinstance(pk.decode(bytes([3, 0, 0, 0, 0, 7, 0, 1])), pk.PacketError)  # bad axis
    assert isinstance(pk.decode(None), pk.PacketError)  # type: ignore[arg-type]


def test_crc8_detects_single_byte_changes() -> None:
    raw = bytes(range(20))
    for i in range(len(raw)):
        changed = bytearray(raw)
        changed[i] ^= 0x10
        assert pk.crc8(bytes(changed)) != pk.crc8(raw)
