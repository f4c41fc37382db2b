"""Diffusion through a tiny lattice world: every module gets every fragment exactly once, in
cyclic structures and under packet loss, and learns its true coordinates, axis and orientation."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from vm_fakes import Placed, World, line, random_structure

from vm import navigation as nav
from vm.isa.assembler import assemble
from vm.roles import RoleTable

SPREAD = assemble("SET_ROLE_NOTIFY 1\nMIGRATE_CONTINUE")
ROLES = RoleTable({1: "Module", 2: "Front"}, {2: frozenset({1})})

# car8-cyclic of docs/simulator.md: car7 plus EW (1,-1,0), closing a cycle driver - axle - wheel... - driver
CAR8 = [Placed((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY),
        Placed((0, 1, -1), nav.UP_DOWN, nav.MAPPINGS[3]),
        Placed((0, -1, -1), nav.UP_DOWN, nav.MAPPINGS[5]),
        Placed((1, 1, -2), nav.EAST_WEST, nav.MAPPINGS[1]),
        Placed((-1, 1, -2), nav.EAST_WEST, nav.MAPPINGS[6]),
        Placed((1, -1, -2), nav.EAST_WEST, nav.MAPPINGS[2]),
        Placed((-1, -1, -2), nav.EAST_WEST, nav.MAPPINGS[7]),
        Placed((1, -1, 0), nav.EAST_WEST, nav.MAPPINGS[4])]


def check_learned(world: World) -> None:
    for vm, p in zip(world.vms, world.placed, strict=True):
        assert (vm.position, vm.axis, vm.mapping) == (p.position, p.axis, p.mount)


def runs(world: World) -> list[int]:
    return [sum(1 for _, k, _ in vm.event_log if k == "program") for vm in world.vms]


def test_car8_cyclic_runs_once_everywhere() -> None:
    world = World(CAR8, ROLES)
    assert len(world.links) > 2 * (len(CAR8) - 1)  # there is a cycle
    world.vms[0].inject(SPREAD)
    world.run(1.0)
    assert runs(world) == [1] * len(CAR8)
    assert [vm.programs_run for vm in world.vms] == [1] * len(CAR8)
    assert sum(vm.duplicates for vm in world.vms) > 0  # copies did come round the cycle
    check_learned(world)
    assert all(vm.errors == [] for vm in world.vms)


@pytest.mark.parametrize("seed", range(4))
def test_ten_percent_loss_still_reaches_everyone_once(seed: int) -> None:
    world = World(random_structure(20, random.Random(seed)), ROLES, loss=0.10, seed=seed)
    world.vms[0].inject(SPREAD)
    world.vms[0].inject(assemble("PUSH 1\nSET_LED 7\nMIGRATE_CONTINUE"))
    world.run(4.0)
    assert world.dropped > 0
    assert runs(world) == [2] * 20
    check_learned(world)
    assert all(vm.role == 1 and vm.led == 7 for vm in world.vms)
    # robust notifications: every connected neighbour's role is known
    for vm in world.vms:
        for v in range(8):
            if vm.connected_virtual() >> v & 1:
                assert vm.neighbour_roles[v] == 1


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 25), st.integers(0, 10_000), st.sampled_from([0.0, 0.1, 0.3]))
def test_random_structures_learn_true_coordinates(n: int, seed: int, loss: float) -> None:
    """Every module runs the program exactly once and learns its frame. At 30 % loss a hop can
    need several retransmissions with back-off (about 2-3 s apart), so the run goes on until
    every module has the program, up to a horizon with room for about a dozen attempts a hop."""
    world = World(random_structure(n, random.Random(seed)), ROLES, loss=loss, seed=seed)
    world.vms[0].inject(SPREAD)
    horizon = 30.0 if loss > 0.2 else 6.0
    elapsed = 0.0
    while elapsed < horizon and 0 in runs(world):
        world.run(1.0)
        elapsed += 1.0
    world.run(2.0)  # late retransmissions must not run the program again
    assert runs(world) == [1] * n
    check_learned(world)


def test_commands_reach_every_instance_once_under_loss() -> None:
    world = World(random_structure(15, random.Random(7)), ROLES, loss=0.10, seed=3)
    world.vms[0].inject(assemble("""
        COORD_Y
        PUSH 0
        GREATER
        IF_FALSE_GOTO plain
        SET_ROLE_NOTIFY 2
        MIGRATE_CONTINUE
    plain:
        SET_ROLE_NOTIFY 1
        MIGRATE_CONTINUE
    """))
    world.run(3.0)
    world.vms[0].inject(assemble("SEND_COMMAND 2 ROTATE_DEGREES 9\nEND_TERMINATE"))
    world.run(3.0)
    for vm, p in zip(world.vms, world.placed, strict=True):
        expected = [("rotate_by", 90.0)] if p.position[1] > 0 else []
        assert vm.hal.calls == expected


def test_snake_line_end_to_end() -> None:
    world = World(line(12), ROLES, loss=0.1, seed=1)
    world.vms[0].inject(SPREAD)
    world.run(4.0)
    assert runs(world) == [1] * 12
    check_learned(world)


def test_corruption_and_delay_with_link_checksum() -> None:
    world = World(random_structure(20, random.Random(11)), ROLES, loss=0.1, corrupt=0.1, max_delay=5,
                  seed=5, checksum=True)
    world.vms[0].inject(SPREAD)
    world.run(5.0)
    assert runs(world) == [1] * 20
    check_learned(world)
    assert sum(vm.bad_packets for vm in world.vms) > 0
    assert all(vm.errors == [] for vm in world.vms)


def test_delay_reorders_but_nothing_runs_twice() -> None:
    world = World(CAR8, ROLES, loss=0.1, max_delay=40, seed=2)
    world.vms[0].inject(SPREAD)
    world.run(4.0)
    assert runs(world) == [1] * len(CAR8)
    check_learned(world)


def test_detection_broadcasts_a_user_command() -> None:
    """A miniature obstacle program: every module installs user command 0 (rotate by 10×arg
    degrees); the entry watches sensor 3 and, on a detection, sends user command 0 to all."""
    world = World(CAR8, ROLES, loss=0.1, seed=4)
    world.vms[0].inject(assemble("""
        SET_ROLE_NOTIFY 1
        INSTALL_COMMAND 1 USER_0 c c_end-c
        MIGRATE_CONTINUE
    c:  PUSH_ARGUMENT 0
        EVAL_COMMAND_STACK_ARG ROTATE_DEGREES
        END_TERMINATE
    c_end:
    """))
    world.vms[0].inject(assemble("""
        HANDLE_EVENT 3 h h_end-h
        END_TERMINATE
    h:  DISABLE_EVENT 3
        SEND_COMMAND 1 USER_0 -9
        END_TERMINATE
    h_end:
    """))
    world.run(2.0)
    world.hals[0].sensors = {3}
    world.run(2.0)
    assert all(h.calls == [("rotate_by", -90.0)] for h in world.hals)
    assert [k for _, k, _ in world.vms[0].event_log].count("handler") == 1


def test_a_handler_may_spread_again_on_each_detection() -> None:
    world = World(line(5), ROLES, seed=1)
    world.vms[0].inject(assemble("""
        HANDLE_EVENT 0 h h_end-h
        END_TERMINATE
    h:  EVAL_COMMAND STOP 0
        MIGRATE_CONTINUE
    h_end:
    """))
    world.run(0.5)
    for _ in range(2):
        world.hals[0].sensors = {0}
        world.run(0.5)
        world.hals[0].sensors = set()
        world.run(0.5)
    assert all(len(h.calls) == 2 for h in world.hals)
