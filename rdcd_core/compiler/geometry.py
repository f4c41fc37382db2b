"""Which virtual channels face which direction, per axis (dcd-vm.md §5). Copied from the table
of the spec because rdcd_core may import only ``vm.isa`` of the VM."""

from __future__ import annotations

EW, NS, UD = 1, 2, 3
OFFSETS: dict[int, tuple[tuple[int, int, int], ...]] = {
    NS: ((0, 1, 1), (-1, 1, 0), (0, 1, -1), (1, 1, 0), (0, -1, 1), (-1, -1, 0), (0, -1, -1), (1, -1, 0)),
    EW: ((1, 0, 1), (1, 1, 0), (1, 0, -1), (1, -1, 0), (-1, 0, 1), (-1, 1, 0), (-1, 0, -1), (-1, -1, 0)),
    UD: ((0, 1, 1), (1, 0, 1), (0, -1, 1), (-1, 0, 1), (0, 1, -1), (1, 0, -1), (0, -1, -1), (-1, 0, -1)),
}
# direction code -> (coordinate index, sign)
DIRECTIONS: dict[int, tuple[int, int]] = {4: (0, 1), 5: (0, -1), 6: (1, 1), 7: (1, -1), 8: (2, 1), 9: (2, -1)}
DIRECTION_NAMES = {4: "EAST", 5: "WEST", 6: "NORTH", 7: "SOUTH", 8: "UP", 9: "DOWN"}
ROLE_DIRECTION_OPS = {9: "CONNECTED_DOWN_ROLE", 8: "CONNECTED_UP_ROLE", 4: "CONNECTED_EAST_ROLE",
                      5: "CONNECTED_WEST_ROLE", 6: "CONNECTED_NORTH_ROLE", 7: "CONNECTED_SOUTH_ROLE"}


def facing(axis: int, direction: int) -> int:
    """The connset of channels of a module with ``axis`` that face ``direction``."""
    index, sign = DIRECTIONS[direction]
    mask = 0
    for channel, offset in enumerate(OFFSETS[axis]):
        if offset[index] * sign > 0:
            mask |= 1 << channel
    return mask


LOCAL_STATES: tuple[tuple[int, int], ...] = tuple((axis, c) for axis in (EW, NS, UD) for c in range(256))
ALL_STATES = (1 << len(LOCAL_STATES)) - 1
