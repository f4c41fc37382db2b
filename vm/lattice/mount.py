"""How a module sits on its lattice place: which physical connector is at each virtual channel.

A module's axis line is fixed by its position (docs/vm.md); what remains free is one of 8
symmetries that keep that line: a quarter-turn ``rotation`` about the axis (0..3) and whether the
module is ``mirrored`` (turned end over end, so its physical north hemisphere, connectors 0-3,
lies on the structure's virtual hemisphere 4-7). These are exactly the 8 maps the VM's
virtual-to-physical ring rule can learn, so a module that learns its map from one packet learns
its true mount.

Definition: not mirrored, virtual channel 0 holds physical ``rotation``; mirrored, it holds
physical ``4 + rotation``. The other channels follow the rings 0-3 / 4-7 rotated in step, with
the mirror pairing 0<->4, 1<->7, 2<->6, 3<->5 of docs/vm.md
"""

from __future__ import annotations

from dataclasses import dataclass

from vm.navigation import MIRROR


@dataclass(frozen=True, slots=True)
class Mount:
    rotation: int = 0
    mirrored: bool = False

    def __post_init__(self) -> None:
        if self.rotation not in (0, 1, 2, 3):
            raise ValueError(f"mount rotation must be 0..3, got {self.rotation!r}")

    def physical_of(self, virtual: int) -> int:
        """The physical connector that sits at virtual channel ``virtual``."""
        return self.physical_map()[virtual]

    def virtual_of(self, physical: int) -> int:
        """The virtual channel at which physical connector ``physical`` sits."""
        return self.physical_map().index(physical)

    def physical_map(self) -> tuple[int, ...]:
        """Physical connector of each virtual channel 0..7."""
        if not self.mirrored:
            return tuple(4 * (v // 4) + (v % 4 + self.rotation) % 4 for v in range(8))
        k = (-self.rotation) % 4
        return tuple(MIRROR[4 * (v // 4) + (v % 4 + k) % 4] for v in range(8))

    def to_json(self) -> dict[str, object]:
        return {"rotation": self.rotation, "mirrored": self.mirrored}


IDENTITY = Mount()
ALL_MOUNTS: tuple[Mount, ...] = tuple(Mount(r, m) for m in (False, True) for r in range(4))
