"""A change of shape past PyBullet's links per body (sim.robot.MAX_LINKS) is a failed change with
its cause, said as an event; the run goes on in the shape it had (it used to end the run)."""

from __future__ import annotations

import pytest

from sim.config import load_config
from sim.robot import MAX_LINKS
from sim.world import PhysicsWorld
from vm import navigation
from vm.lattice.mount import Mount
from vm.lattice.outside import OutsideChange
from vm.lattice.structure import ModuleSpec
from vm.roles import RoleTable

LONGEST = MAX_LINKS - 2  # snakeN has N + 1 rigid parts, and the anchor is one link more


def _attach_at_the_end(t: float) -> OutsideChange:
    return OutsideChange(t, "attach", LONGEST, (1, LONGEST, 0), navigation.EAST_WEST, Mount(1),
                         text=f"{t:g}s:attach {LONGEST} at 1,{LONGEST},0 rot 1")


@pytest.mark.slow
def test_an_outside_attach_past_the_link_limit_fails_with_its_cause_and_the_run_goes_on() -> None:
    world = PhysicsWorld(load_config(f"snake{LONGEST}"), changes=[_attach_at_the_end(0.1)])
    try:
        world.add_runtimes(RoleTable(), 0)
        bodies = list(world.robot.bodies)
        world.advance(0.3)
        kinds = [(e[1], e[2]) for e in world.events]
        assert kinds == [(LONGEST, "outside"), (LONGEST, "outside_failed")]
        detail = world.events[-1][3]
        assert detail["cause"] == "link_limit"
        assert f"{MAX_LINKS} rigid parts in one body" in detail["reason"]
        assert f"at most {MAX_LINKS - 1}" in detail["reason"]
        assert LONGEST not in world.structure.modules and LONGEST not in world.robot.modules
        assert world.robot.bodies == bodies and world.shape.rebuilds == 0  # nothing was built again
        world.advance(0.2)  # and the run goes on
        assert world.time >= 0.5
    finally:
        world.close()


@pytest.mark.slow
def test_attach_and_detach_near_the_link_limit() -> None:
    """The same attach asked through ``Shape.attach`` fails as ``attach_failed``; a detach that
    leaves fewer parts is made, and then the attach fits."""
    world = PhysicsWorld(load_config(f"snake{LONGEST}"))
    try:
        world.add_runtimes(RoleTable(), 0)
        spec = ModuleSpec(LONGEST, (1, LONGEST, 0), navigation.EAST_WEST, Mount(1))
        assert world.shape.attach(spec) == 0
        assert [e[2] for e in world.events] == ["attach_failed"]
        assert world.events[-1][3]["cause"] == "link_limit"
        assert world.shape.detach(LONGEST - 1) == 1  # the last module: one rigid part fewer
        world.advance(0.05)
        assert world.shape.rebuilds == 1
        again = ModuleSpec(LONGEST, (0, LONGEST - 1, 0), navigation.NORTH_SOUTH)  # on the freed cell
        assert world.shape.attach(again) == 1
        world.advance(0.05)
        assert world.shape.rebuilds == 2 and LONGEST in world.robot.modules
        assert [e[3].get("cause") for e in world.events].count("link_limit") == 1
    finally:
        world.close()
