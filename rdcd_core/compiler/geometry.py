"""Which virtual channels face which direction, per axis (docs/vm.md), and the local states
discovery reasons over. The channel table is the checker's (``semantics.statespace``): rdcd_core
may import only ``vm.isa`` of the VM, so it cannot read ``vm.navigation``."""

from __future__ import annotations

from rdcd_core.semantics.statespace import AXES, FACING
from rdcd_core.types import PREDEFINED_VALUES, Type

DIRECTION_NAMES = {v.code: name for name, v in PREDEFINED_VALUES.items() if v.type is Type.DIR}
ROLE_DIRECTION_OPS = {code: f"CONNECTED_{name}_ROLE" for code, name in DIRECTION_NAMES.items()}


def facing(axis: int, direction: int) -> int:
    """The connset of channels of a module with ``axis`` that face ``direction``."""
    return FACING[(axis, direction)]


LOCAL_STATES: tuple[tuple[int, int], ...] = tuple((axis, c) for axis in AXES for c in range(256))
ALL_STATES = (1 << len(LOCAL_STATES)) - 1
