"""examples/snake_gait.rdcd (issue 17): in the lattice world every module of a snake learns its
place in the wave (its distance from the head modulo 4, as `side`), every Spine twists once by 200
degrees, alternately one way and the other, and every Spoke turns its wheel continuously, the
direction alternating with its place; in the physics world the snake crawls head first, far
further than snake_wave drifts."""

from __future__ import annotations

import math

import pytest

from sim.config import load_config
from sim.run import Options, simulate
from tests.state.state_harness import compiled, hop_distances, run

SNAKES = ("snake5", "snake6", "snake7", "snake10", "snake15", "snake30")


def _expected_side(distance: int) -> int:
    return 1 if distance % 4 < 2 else 2


@pytest.mark.parametrize("loss", (0.0, 0.1))
@pytest.mark.parametrize("config", SNAKES)
def test_every_module_learns_its_place_in_the_wave(config: str, loss: float) -> None:
    result = run("snake_gait.rdcd", config, seed=5, loss=loss, quiet_s=8.0)
    shape = result.structure
    distances = hop_distances(shape)  # the head is the entry module
    tail = max(shape.ids())
    roles = result.roles()
    sides = result.values("side")
    # a NORTH_SOUTH tail plays no role and keeps the initial 0
    assert sides == {m: _expected_side(distances[m]) if roles[m] else 0 for m in shape.ids()}
    for m, spec in shape.modules.items():
        if m == shape.entry:
            assert roles[m] == "Head"
        elif spec.axis == shape.modules[1].axis:
            assert roles[m] == "Spoke"
        elif m == tail:
            assert roles[m] is None  # a NORTH_SOUTH tail has nothing to do
        else:
            assert roles[m] == "Spine"
    assert result.errors() == {}


def test_spines_twist_once_and_spokes_roll_by_their_place() -> None:
    result = run("snake_gait.rdcd", "snake10", quiet_s=8.0)
    world, shape = result.world, result.structure
    world.advance(10.0)  # both halves of every twist are done
    roles = result.roles()
    sides = result.values("side")
    for m in shape.ids():
        angle = world.hals[m].joint_angle_deg()
        if roles[m] == "Spine":  # +200 or -200 degrees, read as -160 or +160
            assert abs(angle - (-160 if sides[m] == 2 else 160)) <= 2.0, (m, angle)
    before = {m: world.hals[m].joint_angle_deg() for m in shape.ids()}
    world.advance(0.5)
    for m in shape.ids():
        turned = (world.hals[m].joint_angle_deg() - before[m] + 180) % 360 - 180
        if roles[m] == "Spoke":  # half a second at one turn in 6 s: 30 degrees
            assert abs(turned - (30 if sides[m] == 2 else -30)) <= 3.0, (m, turned)
        else:
            assert abs(turned) <= 0.5, (m, turned)  # the twists are done once, never again


@pytest.mark.slow
@pytest.mark.parametrize("config", ["snake5", "snake7"])
def test_the_snake_crawls_head_first_in_the_physics_world(config: str) -> None:
    gait, towards_head = displacement("snake_gait.rdcd", config, 30.0)
    wave, _ = displacement("snake_wave.rdcd", config, 30.0)
    assert towards_head > 0.8 * gait, (towards_head, gait)  # the head is at the south end
    assert gait > 1.0, gait  # about 1.6 m in 30 s; the wheels alone roll 1.85 m
    assert gait > 5 * wave, (gait, wave)


def displacement(example: str, config: str, duration: float) -> tuple[float, float]:
    """Net distance (m) the robot's centre moved in the physics world (as benchmarks/snake_gait.py),
    and how far of it toward -y."""
    report = simulate(compiled(example), load_config(config),
                      Options(world="physics", config=config, obstacle="none", duration=duration))
    (_, x0, y0, _), (_, x1, y1, _) = report["trajectory"][0], report["trajectory"][-1]
    return math.hypot(x1 - x0, y1 - y0), y0 - y1
