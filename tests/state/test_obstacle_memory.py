"""examples/obstacle_memory.rdcd in the lattice world: the paper's car counts its detections in
module state and stops for good after the third (issue 17). An obstacle cell is put ahead of a
front wheel's watched sensor until the handler fires, then taken away; this is repeated until
the car has detected three times, and once more to show that nothing watches any longer."""

from __future__ import annotations

import pytest

from sim.config import load_config
from sim.obstacles import Box
from sim.run import inject_program, role_table
from sim.world import PhysicsWorld
from tests.integration.lattice_harness import (
    CARS,
    ROOT,
    WATCHED_SENSOR,
    LatticeRun,
    _handlers,
    _spin,
    compiled,
    front_wheel,
    start,
)

PROGRAM = ROOT / "examples" / "obstacle_memory.rdcd"
BACK_S = 30.0  # a Reverse lasts three joint turns (18 s); the wheels then watch again


def _stops(run: LatticeRun, module: int) -> int:
    index = next(s.index for s in compiled("default", PROGRAM).states if s.name == "stops")
    return run.world.runtimes[module].state[index]


def _detect(run: LatticeRun, cell: tuple[int, int, int]) -> list[int]:
    """Show the obstacle for up to 3 s (until a handler fires), hide it, let the car react."""
    world = run.world
    since = len(world.events)
    world.set_obstacles(frozenset({cell}))
    t0 = world.now()
    while world.now() - t0 < 3.0 and not _handlers(world, since):
        world.advance(0.01)
    world.set_obstacles(frozenset())
    world.advance(BACK_S)
    return [m for _, m in _handlers(world, since)]


@pytest.mark.parametrize("config", CARS)
def test_the_car_stops_for_good_after_the_third_detection(config: str) -> None:
    run = start(config, seed=2, path=PROGRAM)
    assert run.problems() == []
    structure, world = run.structure, run.world
    wheels = {m: r for m, r in structure.expected_roles.items() if r in WATCHED_SENSOR}
    axles = [m for m, r in structure.expected_roles.items() if r == "Axle"]
    detector, cell = front_wheel(structure)
    for detection in (1, 2, 3):
        assert _detect(run, cell) == [detector], f"detection {detection}"
        assert {m: _stops(run, m) for m in wheels} == dict.fromkeys(wheels, detection)
        names = world.role_table.name
        for m, base in wheels.items():
            history = [names(r) for _, r in world.runtimes[m].role_history]
            assert history.count(f"Reverse@{base}") == min(detection, 2), (m, history)
        spins = {m: _spin(world, m) for m in wheels}
        if detection < 3:  # back on their way after reversing
            assert all(spins[m] * (1 if wheels[m] == "RightWheel" else -1) > 0 for m in wheels), spins
        else:  # stopped for good
            assert all(s == 0 for s in spins.values()), spins
    assert _detect(run, cell) == []  # a fourth obstacle: no sensor is watched any more
    world.advance(30.0)
    assert all(_spin(world, m) == 0 for m in wheels)
    assert world.roles_by_name() == structure.expected_roles
    assert all(abs(world.hals[m].joint_angle_deg()) <= 0.5 for m in axles)
    assert {m: _stops(run, m) for m in wheels} == dict.fromkeys(wheels, 3)
    assert run.errors() == {}


def test_packet_loss_still_counts_to_three() -> None:
    run = start("car7", seed=4, loss=0.1, path=PROGRAM)
    wheels = [m for m, r in run.structure.expected_roles.items() if r in WATCHED_SENSOR]
    _, cell = front_wheel(run.structure)
    for _ in range(3):
        _detect(run, cell)
    assert {m: _stops(run, m) for m in wheels} == dict.fromkeys(wheels, 3)
    assert all(_spin(run.world, m) == 0 for m in wheels)



def test_one_obstacle_seen_by_both_front_wheels_counts_once() -> None:
    run = start("car7", seed=1, path=PROGRAM)
    structure, world = run.structure, run.world
    wheels = {m: r for m, r in structure.expected_roles.items() if r in WATCHED_SENSOR}
    cells = set()
    for m, role in wheels.items():
        if structure.modules[m].position[1] > 0:
            x, y, z = structure.modules[m].position
            dx, dy, dz = structure.physical_direction(m, WATCHED_SENSOR[role])
            cells.add((x + 2 * dx, y + 2 * dy, z + 2 * dz))
    assert len(cells) == 2
    since = len(world.events)
    world.set_obstacles(frozenset(cells))
    world.advance(0.5)
    world.set_obstacles(frozenset())
    world.advance(BACK_S)
    assert len(_handlers(world, since)) == 2  # both front wheels fired ...
    assert {m: _stops(run, m) for m in wheels} == dict.fromkeys(wheels, 1)  # ... one detection


def _arena(half: float) -> list[Box]:
    """Four walls around the start, ``half`` metres from it: the car keeps meeting one."""
    side = 2 * half + 0.1
    return [Box(0.0, half, side, 0.05, "wall"), Box(0.0, -half, side, 0.05, "wall"),
            Box(half, 0.0, 0.05, side, "wall"), Box(-half, 0.0, 0.05, side, "wall")]


@pytest.mark.slow
def test_the_car_stops_for_good_in_an_arena_of_walls() -> None:
    """The physics world: car7 inside four walls meets a wall three times (about 18 s, 62 s and
    110 s in), and after the third stays where it is with every wheel's joint stopped."""
    program = compiled("default", PROGRAM)
    structure = load_config("car7")
    world = PhysicsWorld(structure, obstacles=_arena(1.2), seed=0)
    try:
        runtimes = world.add_runtimes(role_table(program), seed=0)
        inject_program(program, runtimes[structure.entry].inject)
        index = next(s.index for s in program.states if s.name == "stops")
        wheels = [m for m, r in structure.expected_roles.items() if r in WATCHED_SENSOR]
        stopped_at = None
        while world.time < 170.0 and stopped_at is None:
            world.advance(1.0)
            if all(runtimes[m].state[index] == 3 for m in wheels):
                stopped_at = world.time
        assert stopped_at is not None, {m: runtimes[m].state[index] for m in wheels}
        world.advance(5.0)  # the last commands are carried out
        still = world.centre()
        world.advance(30.0)
        x, y = world.centre()
        assert abs(x - still[0]) + abs(y - still[1]) < 0.01, (still, (x, y))
        assert all(world.joints[m].velocity == 0 and world.joints[m].target is None for m in wheels)
        names = role_table(program).name
        for m in wheels:  # reversed after the first two detections only
            history = [names(r) for _, r in runtimes[m].role_history]
            assert sum(name.startswith("Reverse") for name in history) == 2, (m, history)
            assert runtimes[m].state[index] == 3
        assert not any(r.errors for r in runtimes.values())
    finally:
        world.close()
