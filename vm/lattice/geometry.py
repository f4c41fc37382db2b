"""A module's body frame and its rigid placement in the structure frame.

Body frame: the joint runs along body +y; the physical north hemisphere (connectors 0-3) is at
+y and connector ``p`` points along the NS row of docs/vm.md (connector 0 up-north, 1
west-north, ...), i.e. a module at the origin with axis NS and the identity mount has its body
frame equal to the structure frame. ``placement`` gives the proper rotation (integer matrix,
determinant +1) that carries the body frame of a module onto the structure frame; a world with
physics uses it to place the module's hemispheres and connectors.

Joint sign: a positive joint motion (positive speed, "clockwise", increasing angle) turns the
north hemisphere relative to the south one by the right-hand rule about body +y (clockwise as seen
from the south hemisphere). With this rule and the shipped mounts, the obstacle program's wheels
(RightWheel +1, LeftWheel -1) all roll the car towards +y.
"""

from __future__ import annotations

from functools import lru_cache

from vm import navigation
from vm.lattice.mount import Mount

Vec = tuple[int, int, int]
Matrix = tuple[Vec, Vec, Vec]  # rows


def body_direction(physical: int) -> Vec:
    """Direction of physical connector ``physical`` in the module's own body frame."""
    return navigation.offset(navigation.NORTH_SOUTH, physical)


@lru_cache(maxsize=64)  # 3 axes x 8 mounts; pure
def placement(axis: int, mount: Mount) -> Matrix:
    """Rotation R (rows) with R @ body_direction(p) = the structure-frame offset of connector p."""
    def world(p: int) -> Vec:
        return navigation.offset(axis, mount.virtual_of(p))

    def half(a: Vec, b: Vec, sign: int) -> Vec:
        return tuple((x + sign * y) // 2 for x, y in zip(a, b, strict=True))  # type: ignore[return-value]

    # body e_x = (b3 - b1)/2, e_y = (b0 + b2)/2, e_z = (b0 - b2)/2
    cols = (half(world(3), world(1), -1), half(world(0), world(2), 1), half(world(0), world(2), -1))
    return tuple(tuple(cols[j][i] for j in range(3)) for i in range(3))  # type: ignore[return-value]


def apply(m: Matrix, v: Vec) -> Vec:
    return tuple(sum(m[i][j] * v[j] for j in range(3)) for i in range(3))  # type: ignore[return-value]


def determinant(m: Matrix) -> int:
    (a, b, c), (d, e, f), (g, h, i) = m
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def free_spin_axis(axis: int, mount: Mount, free_hemisphere: int, speed: int) -> Vec:
    """Structure-frame axis about which (right-hand rule) the free hemisphere (0 = physical north,
    1 = south) turns when the other is held and the joint moves with ``speed``."""
    north = apply(placement(axis, mount), (0, 1, 0))
    sign = (1 if speed > 0 else -1) * (1 if free_hemisphere == 0 else -1)
    return tuple(sign * c for c in north)  # type: ignore[return-value]
