"""Structures that change in the physics world (sim.reshape, sim.topology): quarter turns carried
by the joint under gravity, the torque limit, the latch tolerance, splits, outside changes."""

from __future__ import annotations

import numpy as np
import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim import params
from sim.config import load_config
from sim.obstacles import parse_obstacle
from sim.run import Options, inject_program, role_table, simulate
from sim.world import PhysicsWorld
from tests.conftest import EXAMPLES
from tests.sim.helpers import obstacle_program
from vm import navigation
from vm.isa.assembler import assemble
from vm.lattice.mount import Mount
from vm.lattice.outside import OutsideChange
from vm.lattice.structure import ModuleSpec, Structure, make_structure
from vm.lattice.world import LatticeWorld
from vm.roles import RoleTable


def _world(structure: Structure) -> tuple[PhysicsWorld, list[tuple]]:
    world = PhysicsWorld(structure)
    world.add_runtimes(RoleTable(), 0)
    return world, world.events


def _wait(world: PhysicsWorld, mid: int, limit: float = 6.0) -> int | None:
    """Run until module ``mid``'s action has its answer (or ``limit`` seconds)."""
    end = world.time + limit
    while world.hals[mid].action_result() is None and world.time < end:
        world.advance(0.25)
    return world.hals[mid].action_result()


def stair(n: int) -> Structure:
    """``n`` modules lying on the ground on a diagonal: NS at (2k, 2k, 0), EW at (2k+1, 2k+1, 0).
    Every joint turns about a horizontal line, and what it carries sticks out sideways from it."""
    specs = [ModuleSpec(i, (i, i, 0), navigation.NORTH_SOUTH if i % 2 == 0 else navigation.EAST_WEST,
                        Mount(0) if i % 2 == 0 else Mount(1)) for i in range(n)]
    return make_structure(specs, entry=0, name=f"stair{n}")


def ring() -> Structure:
    """Four modules in a ring on the ground; 3 and 2 face each other but are not latched."""
    specs = [ModuleSpec(0, (0, 0, 0), navigation.NORTH_SOUTH),
             ModuleSpec(1, (1, 1, 0), navigation.EAST_WEST, Mount(1)),
             ModuleSpec(2, (2, 0, 0), navigation.NORTH_SOUTH),
             ModuleSpec(3, (1, -1, 0), navigation.EAST_WEST, Mount(1))]
    return make_structure(specs, entry=0, name="ring4", connections=[(0, 1), (1, 2), (0, 3)])


@pytest.mark.slow
def test_a_quarter_turn_carries_the_neighbour_to_its_new_cell_as_the_structure_says() -> None:
    structure = load_config("snake4")
    lattice = LatticeWorld(load_config("snake4"), RoleTable())  # the same action, no physics
    lattice.hals[2].rotate_quarters(-1)
    lattice.advance(2.0)
    assert lattice.hals[2].action_result() == 1
    expected = lattice.structure
    assert expected.modules[3].position == (0, 3, 1)
    world, events = _world(structure)
    try:
        world.advance(0.2)
        start = world.module_centres()[3]
        world.hals[2].rotate_quarters(-1)
        assert world.hals[2].action_result() is None  # under way: the joint takes its time
        assert _wait(world, 2) == 1
        assert structure.modules == expected.modules  # cells, axes, mounts and joint quarters
        assert structure.links() == expected.links()
        end = world.module_centres()[3]
        assert end[2] - start[2] > 0.06  # lifted one lattice step off the ground, by the joint
        kinds = [e[2] for e in events]
        assert kinds == ["rotation_start", "rotation_end"]
        assert events[1][0] - events[0][0] >= 0.25 * params.JOINT_TURN_PERIOD_S * 0.9
    finally:
        world.close()


@pytest.mark.slow
def test_a_turn_that_must_lift_too_much_stalls_and_is_reported() -> None:
    # module 3 carries 4, 5, 6 sticking out 0.08, 0.16, 0.24 m from its axis: 4 N·m > 3 N·m;
    # the other side (0, 1, 2) is as heavy, so neither side can turn
    structure = stair(7)
    world, events = _world(structure)
    try:
        world.advance(0.2)
        world.hals[3].rotate_quarters(1)
        assert _wait(world, 3) == 0
        failed = [e for e in events if e[2] == "rotation_failed"]
        assert failed and failed[0][3]["cause"] == "stalled"
        assert structure.modules[4].position == (4, 4, 0)  # the structure did not move
        world.advance(0.5)  # and nothing raises afterwards
    finally:
        world.close()


@pytest.mark.slow
def test_one_module_lifts_the_load_it_can() -> None:
    structure = stair(5)  # module 3 carries only 4: 0.67 N·m
    world, _ = _world(structure)
    try:
        world.advance(0.2)
        world.hals[3].rotate_quarters(1)
        assert _wait(world, 3) == 1
        assert structure.modules[4].position == (4, 3, 1)
    finally:
        world.close()


@pytest.mark.slow
def test_a_latch_closes_only_within_the_tolerance() -> None:
    structure = ring()
    world, events = _world(structure)
    try:
        world.advance(0.2)
        assert world.shape.gap(3, 2) < params.LATCH_DISTANCE
        # module 0's south hemisphere carries 3 up by 30°: 3's connector 2 leaves 2's connector 5
        world.hals[0].rotate_by(30.0)
        world.advance(1.5)
        gap = world.shape.gap(3, 2)
        assert gap > params.LATCH_DISTANCE
        assert not world.hals[3].other_connector_nearby(2)
        world.hals[3].connect(2)
        assert world.hals[3].action_result() == 0
        assert events[-1][2] == "connect_failed" and events[-1][3]["cause"] == "not_aligned"
        assert not structure.neighbours(3).get(2)
        world.hals[0].rotate_by(-30.0)
        world.advance(1.5)
        assert world.hals[3].other_connector_nearby(2)
        world.hals[3].connect(2)
        assert world.hals[3].action_result() == 1
        assert structure.neighbours(3)[2] == (2, 5)
        world.advance(0.3)  # the bodies follow: the ring is closed, module 0's joint is locked
        assert world.joints[0].joint is None
        assert world.hals[3].is_connected(2)
        world.hals[0].rotate_quarters(1)
        assert world.hals[0].action_result() == 0
        assert events[-1][3]["cause"] == "loop"
    finally:
        world.close()


@pytest.mark.slow
def test_an_unlatch_splits_the_robot_and_the_part_goes_on_running() -> None:
    structure = load_config("snake4")
    world, events = _world(structure)
    try:
        world.advance(0.2)
        link = next(k for k in structure.links() if {k.a, k.b} == {1, 2})
        male, connector = (link.a, link.a_physical) if link.a_physical % 2 == 0 else (link.b, link.b_physical)
        before = world.module_centres()
        world.hals[male].disconnect(connector)
        assert world.hals[male].action_result() == 1
        world.shape.tick()  # what the end of this tick does: the bodies follow the structure
        assert len(world.robot.bodies) == 2
        assert [e[2] for e in events] == ["disconnect", "split"]
        assert events[1][3]["parts"] == [[0, 1], [2, 3]]
        after = world.module_centres()
        assert max(np.linalg.norm(np.subtract(after[m], before[m])) for m in after) < 1e-4  # no jump
        world.hals[3].rotate_continuously(1)  # the part cut off still moves its joints
        world.advance(1.0)
        assert abs(world.hals[3].joint_angle_deg()) > 30
        assert all(0.04 < c[2] < 0.08 for c in world.module_centres().values())  # both lie on the ground
    finally:
        world.close()


@pytest.mark.slow
def test_car7_losing_a_wheel_from_outside_keeps_running() -> None:
    program = obstacle_program()
    world = PhysicsWorld(load_config("car7"), obstacles=parse_obstacle("wall:1.0"),
                         changes=[OutsideChange(2.0, "detach", 6, text="2s:detach 6")])
    try:
        runtimes = world.add_runtimes(role_table(program), 0)
        inject_program(program, runtimes[world.structure.entry].inject)
        world.advance(2.0)
        y0 = world.centre()[1]
        world.advance(3.0)
        assert 6 not in world.structure.modules and 6 not in world.robot.modules
        assert [e[2] for e in world.events][:1] == ["outside"]
        assert world.centre()[1] > y0 + 0.02  # the three-wheeled car still drives forward
        assert len(world.robot.bodies) == 1
    finally:
        world.close()


@pytest.mark.slow
def test_a_program_turning_its_joint_moves_the_structure_as_in_the_lattice_world() -> None:
    code = assemble("PUSH -1\nTURN_QUARTERS\nSET_LED_STACK\nEND_TERMINATE")  # LED = the answer
    lattice = LatticeWorld(load_config("snake4"), RoleTable())
    lattice.inject(code, 2)
    lattice.advance(3.0)
    world = PhysicsWorld(load_config("snake4"))
    try:
        world.add_runtimes(RoleTable(), 0)[2].inject(code)
        world.advance(3.0)
        assert world.hals[2].led == lattice.hals[2].led == 1
        assert world.structure.modules == lattice.structure.modules
        assert [e[2] for e in world.events] == ["rotation_start", "rotation_end"]
    finally:
        world.close()


def test_impossible_actions_are_reported_never_raised() -> None:
    world, events = _world(load_config("snake4"))
    try:
        hal = world.hals[1]
        for action, arg in (("connect", 99), ("connect", -1), ("disconnect", 42), ("connect", 1),
                            ("disconnect", 5)):
            getattr(hal, action)(arg)
            assert hal.action_result() == 0
        world.hals[2].rotate_quarters(1)  # module 3 would pass through the ground
        assert world.hals[2].action_result() == 0
        assert not hal.other_connector_nearby(99)
        assert [e[2] for e in events] == ["connect_failed", "connect_failed", "disconnect_failed",
                                          "connect_failed", "disconnect_failed", "rotation_failed"]
        assert events[-1][3]["cause"] == "ground"
        world.hals[0].rotate_quarters(0)
        assert world.hals[0].action_result() == 1
        world.advance(0.1)
    finally:
        world.close()


@pytest.mark.slow
def test_a_module_attached_from_outside_appears_on_its_cell_and_latches() -> None:
    changes = [OutsideChange(0.5, "attach", 4, (0, 4, 0), navigation.NORTH_SOUTH, text="0.5s:attach 4"),
               OutsideChange(1.0, "stop", 1, text="1s:stop 1")]
    world = PhysicsWorld(load_config("snake4"), changes=changes)
    try:
        world.add_runtimes(RoleTable(), 0)
        world.advance(0.8)
        assert 4 in world.robot.modules and 4 in world.runtimes
        assert world.structure.neighbours(4) and world.hals[4].connected_channels()
        centres = world.module_centres()
        step = np.subtract(centres[4], centres[2])
        assert np.allclose(step, (0.0, 2 * params.LATTICE_UNIT, 0.0), atol=0.01)  # its cell, no fall
        assert len(world.robot.bodies) == 1
        world.advance(0.5)
        assert 1 in world.stopped and world.runtimes[1].halted
        assert [e[2] for e in world.events] == ["outside", "attach", "outside"]
    finally:
        world.close()


@pytest.mark.slow
def test_move_one_moves_and_relatches_the_module_in_physics_as_in_the_lattice() -> None:
    text = (EXAMPLES / "move_one.rdcd").read_text(encoding="utf-8")
    program = compile_model(check_text(text).model, text=text)
    reports = {}
    for world in ("lattice", "physics"):
        options = Options(world=world, config="random4-seed109", obstacle="none", duration=6.0)
        reports[world] = simulate(program, load_config("random4-seed109"), options)
    for report in reports.values():
        assert [m["final_lattice"] for m in report["modules"]][2] == [2, 0, 0]
        wanted = ("rotation_end", "connect", "disconnect")
        kinds = [e["kind"] for e in report["events"] if e["kind"] in wanted]
        assert kinds == ["rotation_end", "connect", "disconnect"]
    assert reports["physics"]["connections"] == reports["lattice"]["connections"]
    assert [m["final_lattice"] for m in reports["physics"]["modules"]] == \
        [m["final_lattice"] for m in reports["lattice"]["modules"]]


def _run_example(name: str, config: str, world: str, duration: float, change: str,
                 obstacle: str = "none") -> dict:
    from vm.lattice.outside import parse_all

    text = (EXAMPLES / name).read_text(encoding="utf-8")
    program = compile_model(check_text(text).model, text=text)
    options = Options(world=world, config=config, obstacle=obstacle, duration=duration,
                      outside_changes=parse_all([change]))
    return simulate(program, load_config(config), options)


@pytest.mark.slow
@pytest.mark.parametrize(("change", "lost"), [("3s:detach 3", {}), ("3s:detach 1", {3: None, 4: None})])
def test_lose_a_wheel_in_physics_the_roles_follow_the_new_shape_as_in_the_lattice(
        change: str, lost: dict) -> None:
    from sim.report import summary

    roles = {}
    for world in ("lattice", "physics"):
        report = _run_example("lose_a_wheel.rdcd", "car7", world, 6.0, change, "wall:1.0")
        roles[world] = {m["id"]: m["final_role"] for m in report["modules"] if m["final_lattice"] is not None}
        assert "roles after the outside changes" in summary(report)
    assert roles["physics"] == roles["lattice"]
    assert all(roles["physics"][m] is None for m in lost)
    assert "Axle" in roles["physics"].values()


@pytest.mark.slow
def test_grow_in_physics_the_attached_module_joins_the_gradient() -> None:
    report = _run_example("grow.rdcd", "snake5", "physics", 5.0, "2s:attach 5 at 1,5,0 rot 1")
    modules = {m["id"]: m for m in report["modules"]}
    assert modules[5]["final_role"] == "Node"
    assert [modules[m]["final_state"]["hops"] for m in range(6)] == [0, 1, 2, 3, 4, 5]
