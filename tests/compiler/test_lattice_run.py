"""The compiled obstacle program runs on the VM in the lattice world (no physics)."""

from __future__ import annotations

import pytest

from sim.config import load_config
from sim.run import role_table
from vm.lattice.world import LatticeWorld

CARS = ["car7", "car11", "car8-cyclic", "car17-wide"]


def start(program, config: str, *, loss: float = 0.0, spaced: bool = True, seed: int = 1):
    structure = load_config(config)
    world = LatticeWorld(structure, role_table(program), seed=seed, packet_loss=loss)
    for name in program.injection:
        world.inject(program.fragment(name).code)
        if spaced:
            world.run_until_quiet(5.0)
    world.advance(5.0)
    return structure, world


@pytest.mark.parametrize("config", CARS)
def test_every_module_takes_its_role(obstacle, config):
    structure, world = start(obstacle, config)
    assert world.roles_by_name() == structure.expected_roles
    assert all(not state.errors for state in world.states())


@pytest.mark.parametrize("config,loss", [("car7", 0.0), ("car11", 0.1), ("car8-cyclic", 0.1)])
def test_roles_also_when_fragments_are_injected_back_to_back(obstacle, config, loss):
    structure, world = start(obstacle, config, loss=loss, spaced=False, seed=7)
    assert world.roles_by_name() == structure.expected_roles


def spin(world, module: int) -> float:
    """Signed joint motion of a module over 0.1 s."""
    before = world.hals[module].joint_angle_deg()
    world.advance(0.1)
    return (world.hals[module].joint_angle_deg() - before + 180) % 360 - 180


def test_obstacle_makes_every_wheel_reverse_and_the_axles_steer(obstacle):
    structure, world = start(obstacle, "car7")
    names = world.roles_by_name()
    wheels = [m for m, role in names.items() if role and role.endswith("Wheel")]
    axles = {m: structure.modules[m].position for m, role in names.items() if role == "Axle"}
    forward = {m: spin(world, m) for m in wheels}
    assert all(v != 0 and (v > 0) == (names[m] == "RightWheel") for m, v in forward.items())
    world.set_obstacles(frozenset((x, 3, z) for x in range(-3, 4) for z in (-2, -1)))
    world.advance(3.0)
    world.set_obstacles(frozenset())
    reversing = world.roles_by_name()
    assert all(reversing[m].startswith("Reverse@") for m in wheels)
    backward = {m: spin(world, m) for m in wheels}
    assert all(backward[m] * forward[m] < 0 for m in wheels)
    angles = {m: round(world.hals[m].joint_angle_deg()) for m in axles}
    for module, position in axles.items():
        assert angles[module] == (30 if position[1] > 0 else -30)
    world.advance(25.0)
    after = world.roles_by_name()
    assert after == structure.expected_roles  # nothing left in Reverse
    assert all(round(world.hals[m].joint_angle_deg()) == 0 for m in axles)
    assert all(spin(world, m) * forward[m] > 0 for m in wheels)  # forward again
    assert all(not state.errors for state in world.states())


def test_snake_segments_take_roles_and_flash(example_programs):
    from sim.config import snake

    program = example_programs["snake_wave.rdcd"]
    structure = snake(6)
    world = LatticeWorld(structure, role_table(program), seed=2)
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(5.0)
    roles = world.roles_by_name()
    assert roles == {0: None, 1: "Body", 2: "Body", 3: "Body", 4: "Body", 5: "Head"}
    x, y, z = structure.modules[5].position
    around = {(x + dx, y + dy, z + dz) for dx in (-2, -1, 0, 1, 2) for dy in (-2, -1, 0, 1, 2)
              for dz in (-2, -1, 0, 1, 2)} - {m.position for m in structure.modules.values()}
    world.set_obstacles(frozenset(around))
    world.advance(2.0)
    assert {m: world.runtimes[m].led for m in roles} == {0: 0, 1: 7, 2: 7, 3: 7, 4: 7, 5: 7}


@pytest.fixture(scope="module")
def obstacle_original(obstacle_text):
    from tests.compiler.conftest import _compile

    return _compile(obstacle_text, target="original")


@pytest.mark.parametrize("config", ["car7", "car11", "car17-wide"])
def test_the_original_targets_code_finds_the_same_roles(obstacle_original, config):
    """The code for the firmware, run in this project's VM (which runs every instruction it uses),
    gives every module the same role (the firmware's own behaviour is the VM profile's test)."""
    structure, world = start(obstacle_original, config)
    assert world.roles_by_name() == structure.expected_roles
    assert all(not state.errors for state in world.states())


def test_the_original_targets_code_reverses_the_wheels(obstacle_original):
    structure, world = start(obstacle_original, "car7")
    names = world.roles_by_name()
    wheels = [m for m, role in names.items() if role and role.endswith("Wheel")]
    forward = {m: spin(world, m) for m in wheels}
    world.set_obstacles(frozenset((x, 3, z) for x in range(-3, 4) for z in (-2, -1)))
    world.advance(3.0)
    world.set_obstacles(frozenset())
    backward = {m: spin(world, m) for m in wheels}
    assert wheels and all(backward[m] * forward[m] < 0 for m in wheels)
