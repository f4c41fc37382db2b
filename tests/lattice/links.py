"""A test helper that changes a lattice world's connections from outside: the world's structure
stays as configured; only the links the network carries and the connectors the modules' hals
report change (``vm.hal.ModuleHal.connected_channels`` is all the runtime sees of it)."""

from __future__ import annotations

from vm.lattice.world import LatticeWorld

Link = tuple[int, int, int, int]  # module a, its connector, module b, its connector


def unlink(world: LatticeWorld, module: int) -> list[Link]:
    """Detach ``module`` from all its neighbours; returns the links removed."""
    ports = world.network._ports  # noqa: SLF001 - a test reaching into the world on purpose
    removed = [(module, pa, b, pb) for pa, (b, pb) in sorted(ports[module].items())]
    for link in removed:
        set_link(world, link, False)
    return removed


def set_link(world: LatticeWorld, link: Link, connected: bool) -> None:
    """Latch (``connected``) or unlatch one link."""
    a, pa, b, pb = link
    ports = world.network._ports  # noqa: SLF001
    for me, mine, other, theirs in ((a, pa, b, pb), (b, pb, a, pa)):
        if connected:
            ports[me][mine] = (other, theirs)
        else:
            ports[me].pop(mine, None)
        world.hals[me]._connected = frozenset(ports[me])  # noqa: SLF001
        world._woken.add(me)  # noqa: SLF001
