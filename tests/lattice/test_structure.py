"""Structures: mounts agree with the VM's ring rule, placements are rigid, links face each other,
invalid structures give one-line errors naming the module."""

from __future__ import annotations

import pytest

from sim.config import load_config, random_structure, shipped_names
from vm import navigation
from vm.lattice.geometry import apply, body_direction, determinant, placement
from vm.lattice.mount import ALL_MOUNTS, IDENTITY, Mount
from vm.lattice.structure import ModuleSpec, Structure, StructureError, make_structure

NS, EW, UD = navigation.NORTH_SOUTH, navigation.EAST_WEST, navigation.UP_DOWN


def test_mounts_are_the_eight_maps_of_the_ring_rule() -> None:
    assert sorted(m.physical_map() for m in ALL_MOUNTS) == sorted(navigation.MAPPINGS)
    for m in ALL_MOUNTS:
        for v in range(8):
            # whichever packet a module receives first, it learns its true mount
            assert navigation.virtual_to_physical(v, m.physical_of(v)) == m.physical_map()
            assert m.virtual_of(m.physical_of(v)) == v


def test_mount_definition() -> None:
    assert Mount(3).physical_of(0) == 3
    assert Mount(1, True).physical_of(0) == 5
    assert IDENTITY.physical_map() == tuple(range(8))
    with pytest.raises(ValueError):
        Mount(4)


@pytest.mark.parametrize("axis", [NS, EW, UD])
def test_placements_are_proper_rotations(axis: int) -> None:
    for m in ALL_MOUNTS:
        r = placement(axis, m)
        assert determinant(r) == 1
        assert all(sum(r[i][k] * r[j][k] for k in range(3)) == (i == j) for i in range(3) for j in range(3))
        for p in range(8):
            assert apply(r, body_direction(p)) == navigation.offset(axis, m.virtual_of(p))
        # the joint (body +y) lies along the module's axis line
        joint = apply(r, (0, 1, 0))
        assert [abs(c) for c in joint] == [1 if a == axis else 0 for a in (EW, NS, UD)]


def _check_links_face_each_other(s: Structure) -> None:
    for link in s.links():
        a, b = s.modules[link.a], s.modules[link.b]
        toward_b = tuple(q - p for p, q in zip(a.position, b.position, strict=True))
        toward_a = tuple(-c for c in toward_b)
        assert apply(placement(a.axis, a.mount), body_direction(link.a_physical)) == toward_b
        assert apply(placement(b.axis, b.mount), body_direction(link.b_physical)) == toward_a
        assert s.neighbours(link.b)[link.b_physical] == (link.a, link.a_physical)


@pytest.mark.parametrize("name", shipped_names())
def test_shipped_links_face_each_other(name: str) -> None:
    _check_links_face_each_other(load_config(name))


def test_random_links_face_each_other() -> None:
    for seed in range(20):
        _check_links_face_each_other(random_structure(30, seed))
        _check_links_face_each_other(random_structure(20, seed, explicit_connections=True))


def test_all_adjacent_pairs_connect_by_default() -> None:
    s = load_config("car8-cyclic")
    assert len(s.links()) == 8  # car7's 6 links + the bridge's 2
    assert s.connected_channels(0) == frozenset({2, 6, 7})  # axles below, bridge south-east
    for mid in s.ids():
        assert len(s.connected_channels(mid)) == len(s.neighbours(mid))


def _spec(mid: int, pos: tuple[int, int, int], axis: int, mount: Mount = IDENTITY) -> ModuleSpec:
    return ModuleSpec(mid, pos, axis, mount)


BASE = [_spec(0, (0, 0, 0), NS), _spec(1, (0, 1, -1), UD)]


@pytest.mark.parametrize("extra, expected", [
    ([_spec(3, (1, 0, 0), NS)], "module 3 at (1, 0, 0): axis NS needs x, y, z all even"),
    ([_spec(3, (1, 1, 1), EW)], "module 3 at (1, 1, 1): axis EW needs x, y odd and z even"),
    ([_spec(3, (1, 1, 1), UD)], "module 3 at (1, 1, 1): axis UD needs y, z odd and x even"),
    ([_spec(3, (0, 1, -1), UD)], "module 3 at (0, 1, -1): place already taken by module 1"),
    ([_spec(1, (1, 1, 0), EW)], "module 1 at (1, 1, 0): module id 1 used twice"),
    ([_spec(3, (4, 4, 4), NS)], "module 3 at (4, 4, 4): not connected to the entry module 0"),
    ([_spec(3, (0, 1, 7), 9)], "module 3 at (0, 1, 7): unknown axis 9 (use EW, NS or UD)"),
    ([_spec(3, (0, 200, 0), NS)], "module 3 at (0, 200, 0): coordinates must lie in -128..127"),
])
def test_invalid_structures(extra: list[ModuleSpec], expected: str) -> None:
    with pytest.raises(StructureError) as info:
        make_structure(BASE + extra)
    message = str(info.value)
    assert message.startswith(expected)
    assert "\n" not in message


def test_entry_must_define_the_frame() -> None:
    with pytest.raises(StructureError, match="module 0 at .*entry module defines the frame"):
        make_structure([_spec(0, (0, 0, 0), NS, Mount(1)), BASE[1]])
    with pytest.raises(StructureError, match="entry module 7: no such module"):
        make_structure(BASE, entry=7)


def test_explicit_connections() -> None:
    three = BASE + [_spec(2, (0, -1, -1), UD)]
    s = make_structure(three, connections=[(0, 1), (0, 2)])
    assert len(s.links()) == 2
    with pytest.raises(StructureError, match="not connected to the entry"):
        make_structure(three, connections=[(0, 1)])
    with pytest.raises(StructureError, match="module 1 at .*listed connection to module 2"):
        make_structure(three, connections=[(0, 1), (0, 2), (1, 2)])
    with pytest.raises(StructureError, match="connection 0-5: no module 5"):
        make_structure(three, connections=[(0, 1), (0, 2), (0, 5)])


def test_free_hemisphere_of_wheels() -> None:
    s = load_config("car7")
    for mid, spec in s.modules.items():
        if spec.axis == EW:  # a wheel: one hemisphere held by the axle, the other free
            held = next(iter(s.connected_channels(mid))) // 4
            assert s.free_hemisphere(mid) == 1 - held
    assert s.free_hemisphere(0) is None  # the driver: both hemispheres carry an axle
