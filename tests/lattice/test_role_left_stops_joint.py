"""A module whose role is taken away by re-discovery after a change of its connections (a round,
vm.runtime_shape) stops its joint, as the STOP command would: a wheel that is no wheel any more
stops turning. A module that keeps its role keeps turning; one that takes its role again starts
again with the role's entry code (docs/vm.md "When discovery runs")."""

from __future__ import annotations

import sys
from pathlib import Path

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from tests.conftest import EXAMPLES
from vm.lattice.outside import parse_all
from vm.lattice.world import LatticeWorld

sys.path.insert(0, str(Path(__file__).resolve().parent))
from links import set_link, unlink  # noqa: E402 - the helper next to this file

EAST_WEST = "self.center_position == EAST_WEST;"
SPIN = "startup go() { self.turnContinuously(1); }"
WHEEL = (f"role Wheel {{ {EAST_WEST} sizeof(self.total_connected()) == 1; {SPIN} }}\nrole Other {{ }}\n"
         "deployment { Wheel, Other }\n")
SPINNER = f"role Spinner {{ {EAST_WEST} {SPIN} }}\nrole Other {{ }}\ndeployment {{ Spinner, Other }}\n"


def running(text: str, changes: tuple[str, ...] = ()) -> LatticeWorld:
    checked = check_text(text)
    assert not checked.has_errors, checked.diagnostics
    program = compile_model(checked.model, text=text)
    assert not program.has_errors, program.diagnostics
    world = LatticeWorld(load_config("car7"), role_table(program), changes=parse_all(list(changes)))
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(10.0)
    return world


def stops(world: LatticeWorld, module: int) -> list[dict]:
    return [detail for _, kind, detail in world.runtimes[module].event_log if kind == "joint_stopped"]


def test_a_wheel_cut_off_is_no_wheel_and_stops_turning_then_turns_again_when_put_back() -> None:
    world = running(WHEEL)
    wheel = next(mid for mid, role in world.roles_by_name().items() if role == "Wheel")
    assert world.hals[wheel].is_turning()
    cut = unlink(world, wheel)
    world.advance(3.0)
    assert world.roles_by_name()[wheel] == "Other"
    assert not world.hals[wheel].is_turning()
    assert stops(world, wheel) == [{"role_left": "Wheel"}]
    assert world.runtimes[wheel].errors == []
    for link in cut:
        set_link(world, link, True)
    world.advance(3.0)
    assert world.roles_by_name()[wheel] == "Wheel"
    assert world.hals[wheel].is_turning()  # the role's entry code ran again


def test_a_module_that_keeps_its_role_keeps_turning() -> None:
    world = running(SPINNER)
    spinners = [mid for mid, role in world.roles_by_name().items() if role == "Spinner"]
    assert spinners and all(world.hals[mid].is_turning() for mid in spinners)
    unlink(world, spinners[0])
    world.advance(3.0)
    assert world.runtimes[spinners[0]].rounds >= 1  # its roles were checked again
    assert world.roles_by_name()[spinners[0]] == "Spinner"  # alone, still east-west
    assert world.hals[spinners[0]].is_turning() and stops(world, spinners[0]) == []


def test_lose_a_wheel_taking_the_axle_away_stops_the_wheels_that_fell_off() -> None:
    """examples/lose_a_wheel.rdcd with "20s:detach 1" (its header): the axle's two wheels are
    modules alone, no Wheel any more, and stop; the other axle's wheels drive on."""
    text = (EXAMPLES / "lose_a_wheel.rdcd").read_text(encoding="utf-8")
    world = running(text, ("20s:detach 1",))
    world.advance(9.5)
    assert all(world.hals[mid].is_turning() for mid in (3, 4, 5, 6))
    world.advance(5.5)
    roles = world.roles_by_name()
    assert roles[3] is None and roles[4] is None
    assert not world.hals[3].is_turning() and not world.hals[4].is_turning()
    assert world.hals[5].is_turning() and world.hals[6].is_turning()
    stopped = sorted((mid, detail["role_left"]) for _, mid, kind, detail in world.events
                     if kind == "joint_stopped")
    assert stopped == [(3, "LeftWheel"), (4, "RightWheel")]
