"""Where the structure's lattice frame is in the physics world, read from the bodies.

Each hemisphere of the physics world has a fixed frame: the structure's lattice frame at the
moment its module was created (``sim.robot``), so its connectors and pole are constants in it.
The structure model (``vm.lattice.structure``) gives each physical hemisphere a *placement*: the
rotation from the module's body frame (``vm.lattice.geometry``) to the structure frame; the south
hemisphere's is the mount's, the north one's is turned by the joint's quarters. A hemisphere seen
in the world and its placement in the model together say where the structure frame is now.
"""

from __future__ import annotations

import numpy as np

from sim import geometry as g
from sim import params
from sim.topology import HemiState
from vm.lattice.geometry import placement
from vm.lattice.motion import compose, quarter_matrix
from vm.lattice.structure import ModuleSpec, directions


def hemi_placement(spec: ModuleSpec, hemisphere: int) -> np.ndarray:
    """Body frame -> structure frame of physical hemisphere ``hemisphere`` (0 north, 1 south)."""
    p = placement(spec.axis, spec.mount)
    if hemisphere == 1 or spec.joint % 4 == 0:
        return np.array(p, dtype=float)
    north = (p[0][1], p[1][1], p[2][1])
    return np.array(compose(quarter_matrix(north, spec.joint), p), dtype=float)


def node_of(spec0: ModuleSpec, hemisphere: int) -> tuple[int, int]:
    """The physics world's key (module, virtual side at creation) of a physical hemisphere."""
    return spec0.id, g.physical_side(spec0, 4 * hemisphere)


def connector_direction(spec0: ModuleSpec, physical: int) -> g.Vec3:
    """Unit direction of a connector in its hemisphere's fixed frame."""
    d = np.array(directions(spec0)[physical], dtype=float)
    return tuple((d / np.linalg.norm(d)).tolist())  # type: ignore[return-value]


def structure_frame(spec0: ModuleSpec, spec: ModuleSpec, hemisphere: int,
                    state: HemiState) -> tuple[np.ndarray, np.ndarray]:
    """(rotation, origin) of the structure frame in the world, as physical hemisphere
    ``hemisphere`` of a module (created as ``spec0``, now ``spec`` in the model) sees it."""
    body = state.rot @ hemi_placement(spec0, hemisphere)
    rot = body @ hemi_placement(spec, hemisphere).T
    origin = state.centre - rot @ (np.array(spec.position, dtype=float) * params.LATTICE_UNIT)
    return rot, origin


def cell_of(rot: np.ndarray, origin: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """A world point in lattice units of the structure frame (not rounded)."""
    return rot.T @ (centre - origin) / params.LATTICE_UNIT
