"""Navigation table, ring rule and parity rule (docs/vm.md) against the original VM's vectors."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vm import navigation as nav

VECTORS = json.loads((Path(__file__).resolve().parents[1] / "data" / "navigation-vectors.json").read_text())
ORIGIN_OF = {nav.NORTH_SOUTH: (0, 0, 0), nav.EAST_WEST: (1, 1, 0), nav.UP_DOWN: (0, 1, 1)}


def test_vector_counts() -> None:
    assert len(VECTORS["virtual2physical"]) == 82
    assert len(VECTORS["receiver"]) == 7


@pytest.mark.parametrize("case", VECTORS["virtual2physical"])
def test_virtual_to_physical_vectors(case: dict[str, int]) -> None:
    mapping = nav.virtual_to_physical(case["incoming_virtual"], case["incoming_physical"])
    assert mapping[case["virtual"]] == case["physical"]


@pytest.mark.parametrize("case", VECTORS["receiver"])
def test_receiver_vectors(case: dict[str, object]) -> None:
    got = nav.receiver(case["x"], case["y"], case["z"], nav.AXIS_BY_NAME[case["r"]], case["in_ch"])
    assert got == (case["ox"], case["oy"], case["oz"], nav.AXIS_BY_NAME[case["orr"]], case["out_ch"])


@pytest.mark.parametrize("axis", nav.AXES)
@pytest.mark.parametrize("v", range(8))
def test_all_24_entries_round_trip(axis: int, v: int) -> None:
    x, y, z = ORIGIN_OF[axis]
    rx, ry, rz, raxis, rv = nav.receiver(x, y, z, axis, v)
    assert nav.axis_for_position(rx, ry, rz) == raxis
    assert nav.receiver(rx, ry, rz, raxis, rv) == (x, y, z, axis, v)
    assert nav.offset(axis, v) == (rx - x, ry - y, rz - z)


def test_offsets_are_lattice_steps_and_distinct() -> None:
    for axis in nav.AXES:
        offsets = {nav.offset(axis, v) for v in range(8)}
        assert len(offsets) == 8
        assert all(sorted(map(abs, o)) == [0, 1, 1] for o in offsets)


def test_channels_facing_examples() -> None:
    ew = nav.EAST_WEST
    assert nav.channels_facing(ew, nav.UP) == 0b0001_0001
    assert nav.channels_facing(ew, nav.DOWN) == 0b0100_0100
    assert nav.channels_facing(ew, nav.EAST) == 0b0000_1111
    assert nav.channels_facing(ew, nav.NORTH) == 0b0010_0010
    for axis in nav.AXES:  # opposite directions never share a channel
        for a, b in ((nav.EAST, nav.WEST), (nav.NORTH, nav.SOUTH), (nav.UP, nav.DOWN)):
            assert nav.channels_facing(axis, a) & nav.channels_facing(axis, b) == 0


def test_ring_rule_recovers_every_orientation_from_any_pair() -> None:
    assert len(nav.MAPPINGS) == 8
    for mapping in nav.MAPPINGS:
        assert sorted(mapping) == list(range(8))
        for v in range(8):
            assert nav.virtual_to_physical(v, mapping[v]) == mapping


def test_inverse() -> None:
    for iv in range(8):
        for ip in range(8):
            v2p = nav.virtual_to_physical(iv, ip)
            p2v = nav.physical_to_virtual(iv, ip)
            assert all(p2v[v2p[v]] == v for v in range(8))
            assert v2p[iv] == ip


def test_parity_rule() -> None:
    assert nav.axis_for_position(0, 0, 0) == nav.NORTH_SOUTH
    assert nav.axis_for_position(-1, 1, 0) == nav.EAST_WEST
    assert nav.axis_for_position(0, -1, 1) == nav.UP_DOWN
    assert nav.axis_for_position(1, 0, 1) is None
    assert nav.axis_for_position(1, 0, 0) is None


def test_map_connset() -> None:
    mapping = nav.virtual_to_physical(0, 4)
    assert nav.map_connset(0b1, mapping) == 1 << 4
    assert nav.map_connset(0xFF, mapping) == 0xFF
