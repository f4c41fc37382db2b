"""The compiled obstacle program (examples/obstacle_avoidance.rdcd, unmodified) on the shipped cars
in the lattice world (docs/simulator.md, "what the obstacle program works means", without the driving):
expected roles, a front wheel's sensor fires, all wheels reverse while the axles steer (front and
rear opposite), then everything returns and nothing is left in Reverse."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.semantics import analyze
from rdcd_core.syntax import parse
from sim.config import load_config
from sim.run import role_table
from vm.lattice.world import LatticeWorld

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def compiled():
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()
    program = compile_model(analyze(parse(text).program), text=text)
    assert not program.has_errors, program.diagnostics
    return program, role_table(program)


def _until_everywhere(world: LatticeWorld, k: int, limit_s: float = 60.0) -> None:
    """Run until every module has received its k-th program (behaviours repeat for ever, so the
    world never becomes quiet)."""
    for _ in range(round(limit_s / 0.1)):
        stored: dict[int, int] = {}
        for _, m, kind, _ in world.events:
            stored[m] = stored.get(m, 0) + (kind == "program")
        if all(stored.get(m, 0) >= k for m in world.structure.modules):
            return
        world.advance(0.1)
    raise AssertionError(f"program {k} did not reach every module in {limit_s} s")


def _spin(world: LatticeWorld, mid: int) -> float:
    """Signed joint motion of module ``mid`` over 0.1 s."""
    before = world.hals[mid].joint_angle_deg()
    world.advance(0.1)
    return (world.hals[mid].joint_angle_deg() - before + 180) % 360 - 180


@pytest.mark.parametrize("name, loss", [("car7", 0.0), ("car11", 0.0), ("car8-cyclic", 0.1),
                                        ("car17-wide", 0.0)])
def test_obstacle_program(compiled, name: str, loss: float) -> None:
    program, table = compiled
    structure = load_config(name)
    world = LatticeWorld(structure, table, seed=3, packet_loss=loss)
    for k, fragment in enumerate(program.injection, start=1):
        world.inject(program.fragment(fragment).code)
        _until_everywhere(world, k)
    world.advance(1.0)
    assert world.roles_by_name() == structure.expected_roles
    wheels = {m: r for m, r in structure.expected_roles.items() if r and r.endswith("Wheel")}
    axles = [m for m, r in structure.expected_roles.items() if r == "Axle"]
    forward = {m: _spin(world, m) for m in wheels}
    assert all((v > 0) == (wheels[m] == "RightWheel") and v != 0 for m, v in forward.items())

    wall = {(x, 3, z) for x in range(-4, 10) for z in range(-4, 2)}
    world.set_obstacles(frozenset(wall))
    world.advance(0.5)
    world.set_obstacles(frozenset())
    detectors = {m for _, m, kind, _ in world.events if kind == "handler"}
    assert detectors and all(structure.modules[m].position[1] > 0 and m in wheels for m in detectors)
    world.advance(1.5)
    roles = world.roles_by_name()
    assert all(roles[m] == f"Reverse@{wheels[m]}" for m in wheels)
    assert all(_spin(world, m) * forward[m] < 0 for m in wheels)
    for m in axles:
        front = structure.modules[m].position[1] > 0
        assert world.hals[m].joint_angle_deg() == pytest.approx(30.0 if front else -30.0)

    world.advance(20.0)  # three turns at one turn in 6 s, and back
    assert world.roles_by_name() == structure.expected_roles
    assert all(world.hals[m].joint_angle_deg() == pytest.approx(0.0) for m in axles)
    assert all(_spin(world, m) * forward[m] > 0 for m in wheels)
    assert all(not s.errors for s in world.states())
