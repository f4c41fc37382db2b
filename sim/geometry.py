"""Where things are on a module: axes, hemispheres and connectors in the world frame.

The world is z-up and, at start, aligned with the structure's lattice frame (docs/vm.md).
Physical connector p of a module faces the lattice direction of the virtual channel its mount
puts it on, so the VM's virtual-to-physical rule agrees with the real geometry.
"""

from __future__ import annotations

import math

from sim import params
from vm import navigation
from vm.lattice.structure import ModuleSpec

Vec3 = tuple[float, float, float]

AXIS_VECTORS: dict[int, Vec3] = {
    navigation.EAST_WEST: (1.0, 0.0, 0.0),
    navigation.NORTH_SOUTH: (0.0, 1.0, 0.0),
    navigation.UP_DOWN: (0.0, 0.0, 1.0),
}
# Virtual hemispheres: +1 holds virtual channels 0-3 (towards +axis), -1 holds 4-7.
PLUS, MINUS = 1, -1


def lattice_to_world(position: tuple[int, int, int]) -> Vec3:
    x, y, z = position
    u = params.LATTICE_UNIT
    return (x * u, y * u, z * u)


def virtual_side(vch: int) -> int:
    return PLUS if vch < 4 else MINUS


def physical_side(spec: ModuleSpec, physical: int) -> int:
    """Which virtual hemisphere (PLUS/MINUS) physical connector ``physical`` lies on."""
    return virtual_side(spec.mount.virtual_of(physical))


def connector_direction(axis: int, vch: int) -> Vec3:
    """Unit vector, in the module's lattice frame, of the connector at virtual channel ``vch``."""
    dx, dy, dz = navigation.offset(axis, vch)
    n = math.sqrt(dx * dx + dy * dy + dz * dz)
    return (dx / n, dy / n, dz / n)


def physical_connector_direction(spec: ModuleSpec, physical: int) -> Vec3:
    return connector_direction(spec.axis, spec.mount.virtual_of(physical))


def hemisphere_pole(axis: int, side: int) -> Vec3:
    ax = AXIS_VECTORS[axis]
    return (ax[0] * side, ax[1] * side, ax[2] * side)


def hemisphere_inertia(axis: int) -> Vec3:
    """Diagonal inertia (about the hemisphere's centre of mass) in world-aligned axes."""
    m, r = params.HEMISPHERE_MASS, params.MODULE_RADIUS
    along = 0.4 * m * r * r
    across = 83.0 / 320.0 * m * r * r
    ax = AXIS_VECTORS[axis]
    return tuple(along if a else across for a in ax)  # type: ignore[return-value]


def scale(v: Vec3, k: float) -> Vec3:
    return (v[0] * k, v[1] * k, v[2] * k)


def add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
