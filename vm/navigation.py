"""Lattice navigation of the DCD-VM (docs/vm.md).

Frame: +x east, +y north, +z up; the entry module sits at (0,0,0) with axis NORTH_SOUTH.
A module's 8 *virtual* channels are its connectors named in that frame; *physical* channels are
its own connector numbers. ``receiver`` gives, for a module sending on a virtual channel, where the
neighbour is, its axis and the virtual channel on which it sees the sender. ``virtual_to_physical``
is the ring rule by which a module learns its orientation from one incoming (virtual, physical)
pair, exactly as the hardware VM did.
"""

from __future__ import annotations

EAST_WEST = 1
NORTH_SOUTH = 2
UP_DOWN = 3
AXES = (EAST_WEST, NORTH_SOUTH, UP_DOWN)
AXIS_NAMES = {EAST_WEST: "EW", NORTH_SOUTH: "NS", UP_DOWN: "UD"}
AXIS_BY_NAME = {"EW": EAST_WEST, "NS": NORTH_SOUTH, "UD": UP_DOWN,
                "EAST_WEST": EAST_WEST, "NORTH_SOUTH": NORTH_SOUTH, "UP_DOWN": UP_DOWN}

EAST = 4
WEST = 5
NORTH = 6
SOUTH = 7
UP = 8
DOWN = 9
DIRECTIONS = (EAST, WEST, NORTH, SOUTH, UP, DOWN)
DIRECTION_NAMES = {EAST: "EAST", WEST: "WEST", NORTH: "NORTH", SOUTH: "SOUTH", UP: "UP", DOWN: "DOWN"}
DIRECTION_BY_NAME = {name: code for code, name in DIRECTION_NAMES.items()}
# Unit vector of each direction code.
DIRECTION_VECTORS: dict[int, tuple[int, int, int]] = {
    EAST: (1, 0, 0), WEST: (-1, 0, 0), NORTH: (0, 1, 0), SOUTH: (0, -1, 0), UP: (0, 0, 1),
    DOWN: (0, 0, -1),
}

CHANNELS = range(8)

Vec = tuple[int, int, int]

# Per sender axis, per virtual channel: (offset, receiver axis, receiver's virtual channel).
_TABLE: dict[int, tuple[tuple[Vec, int, int], ...]] = {
    NORTH_SOUTH: (
        ((0, 1, 1), UP_DOWN, 6), ((-1, 1, 0), EAST_WEST, 3), ((0, 1, -1), UP_DOWN, 2),
        ((1, 1, 0), EAST_WEST, 7), ((0, -1, 1), UP_DOWN, 4), ((-1, -1, 0), EAST_WEST, 1),
        ((0, -1, -1), UP_DOWN, 0), ((1, -1, 0), EAST_WEST, 5),
    ),
    EAST_WEST: (
        ((1, 0, 1), UP_DOWN, 7), ((1, 1, 0), NORTH_SOUTH, 5), ((1, 0, -1), UP_DOWN, 3),
        ((1, -1, 0), NORTH_SOUTH, 1), ((-1, 0, 1), UP_DOWN, 5), ((-1, 1, 0), NORTH_SOUTH, 7),
        ((-1, 0, -1), UP_DOWN, 1), ((-1, -1, 0), NORTH_SOUTH, 3),
    ),
    UP_DOWN: (
        ((0, 1, 1), NORTH_SOUTH, 6), ((1, 0, 1), EAST_WEST, 6), ((0, -1, 1), NORTH_SOUTH, 2),
        ((-1, 0, 1), EAST_WEST, 2), ((0, 1, -1), NORTH_SOUTH, 4), ((1, 0, -1), EAST_WEST, 4),
        ((0, -1, -1), NORTH_SOUTH, 0), ((-1, 0, -1), EAST_WEST, 0),
    ),
}

# Mirror pairing used when the incoming virtual and physical channels lie on different hemispheres.
MIRROR = (4, 7, 6, 5, 0, 3, 2, 1)


def offset(axis: int, vch: int) -> Vec:
    """Offset from a module with ``axis`` to the neighbour on its virtual channel ``vch``."""
    return _TABLE[axis][vch][0]


def receiver(x: int, y: int, z: int, axis: int, vch: int, *, ud_offsets_swapped: bool = False
             ) -> tuple[int, int, int, int, int]:
    """(rx, ry, rz, raxis, rvch) of the neighbour reached by sending on virtual channel ``vch``.
    ``ud_offsets_swapped``: the original VM's bug (docs/vm.md), the x-offsets of a UD
    sender's channels 5 and 7 exchanged, so the receiver is told a wrong x."""
    (dx, dy, dz), raxis, rvch = _TABLE[axis][vch]
    if ud_offsets_swapped and axis == UP_DOWN and vch in _UD_SWAPPED:
        dx = _TABLE[UP_DOWN][_UD_SWAPPED[vch]][0][0]
    return x + dx, y + dy, z + dz, raxis, rvch


_UD_SWAPPED = {5: 7, 7: 5}  # the UD channels whose x-offsets the original VM exchanged


def channels_facing(axis: int, direction: int) -> int:
    """Connset (bit v = virtual channel v) of channels whose offset points along ``direction``."""
    ux, uy, uz = DIRECTION_VECTORS[direction]
    mask = 0
    for v in CHANNELS:
        dx, dy, dz = offset(axis, v)
        if dx * ux + dy * uy + dz * uz > 0:
            mask |= 1 << v
    return mask


def virtual_to_physical(incoming_virtual: int, incoming_physical: int) -> tuple[int, ...]:
    """Entry v = physical channel of virtual channel v, learned from one incoming pair (ring rule)."""
    mirrored = (incoming_virtual < 4) != (incoming_physical < 4)
    rings = [list(MIRROR[:4]), list(MIRROR[4:])] if mirrored else [[0, 1, 2, 3], [4, 5, 6, 7]]
    ring, pos = rings[incoming_virtual // 4], incoming_virtual % 4
    for _ in range(4):
        if ring[pos] == incoming_physical:
            break
        for r in rings:
            if mirrored:  # towards lower index
                r.append(r.pop(0))
            else:  # towards higher index
                r.insert(0, r.pop())
    else:
        raise ValueError(f"no mapping for ({incoming_virtual}, {incoming_physical})")
    return tuple(rings[0] + rings[1])


def invert(mapping: tuple[int, ...]) -> tuple[int, ...]:
    """Inverse of a channel permutation (virtual→physical becomes physical→virtual)."""
    inverse = [0] * len(mapping)
    for i, j in enumerate(mapping):
        inverse[j] = i
    return tuple(inverse)


def physical_to_virtual(incoming_virtual: int, incoming_physical: int) -> tuple[int, ...]:
    """Entry p = virtual channel of physical channel p (inverse of ``virtual_to_physical``)."""
    return invert(virtual_to_physical(incoming_virtual, incoming_physical))


IDENTITY = tuple(CHANNELS)
# The 8 orientations a module can have relative to the frame (4 quarter turns × mirrored or not).
MAPPINGS: tuple[tuple[int, ...], ...] = tuple(sorted({virtual_to_physical(0, p) for p in CHANNELS}))


def axis_for_position(x: int, y: int, z: int) -> int | None:
    """Parity rule: NS where x, y, z are even; EW where x, y are odd; UD where y, z are odd."""
    px, py, pz = x % 2, y % 2, z % 2
    if (px, py, pz) == (0, 0, 0):
        return NORTH_SOUTH
    if (px, py, pz) == (1, 1, 0):
        return EAST_WEST
    if (px, py, pz) == (0, 1, 1):
        return UP_DOWN
    return None


def map_connset(connset: int, mapping: tuple[int, ...]) -> int:
    """Rename the channels of a connset through a permutation (bit c becomes bit mapping[c])."""
    out = 0
    for c in CHANNELS:
        if connset >> c & 1:
            out |= 1 << mapping[c]
    return out
