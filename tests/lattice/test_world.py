"""The lattice world: diffusion reaches every module once, learned frames equal the true ones
(also under loss, corruption and cycles), joints take time, proximity sees obstacle cells."""

from __future__ import annotations

import inspect
import json
import random

import pytest

from sim.config import load_config, random_structure, shipped_names
from vm.hal import ModuleHal
from vm.isa.assembler import assemble
from vm.lattice.hal import LatticeHal
from vm.lattice.world import LatticeWorld
from vm.roles import RoleTable

MIGRATE = bytes([18])  # MIGRATE_CONTINUE
EMPTY = RoleTable()


def _diffuse(structure, *, seed: int = 0, max_s: float = 60.0, **kw) -> LatticeWorld:
    world = LatticeWorld(structure, EMPTY, seed=seed, latency_s=0.001, **kw)
    world.inject(MIGRATE)
    assert world.run_until_quiet(max_s), f"{structure.name}: still busy after {max_s} s"
    return world


def _assert_reached_once_with_true_frames(world: LatticeWorld) -> None:
    for state in world.states():
        assert state.programs_run == 1, f"module {state.id} ran the program {state.programs_run} times"
        assert state.frame_correct, (
            f"module {state.id}: learned {state.position} axis {state.axis} map {state.mapping}, "
            f"true {state.true_position} axis {state.true_axis} map {state.true_mapping}")
        assert not state.errors


def test_hal_implements_the_contract() -> None:
    for name, member in inspect.getmembers(ModuleHal, inspect.isfunction):
        if not name.startswith("_"):
            mine = getattr(LatticeHal, name)
            assert list(inspect.signature(mine).parameters) == list(inspect.signature(member).parameters)


def test_200_random_structures_learn_their_true_frames() -> None:
    rng = random.Random(2024)
    for case in range(200):
        structure = random_structure(rng.randint(1, 50), case, explicit_connections=case % 4 == 3)
        _assert_reached_once_with_true_frames(_diffuse(structure, seed=case))


@pytest.mark.parametrize("seed", range(6))
def test_diffusion_under_ten_percent_loss(seed: int) -> None:
    world = _diffuse(random_structure(40, 100 + seed), seed=seed, packet_loss=0.1)
    assert world.counters.dropped > 0
    _assert_reached_once_with_true_frames(world)


def test_diffusion_under_corruption_and_jitter() -> None:
    # Packets carry no checksum (docs/vm.md), so a corrupted id byte makes a "new" program and a
    # corrupted coordinate that keeps the parity goes unnoticed; only the genuine program is checked.
    world = _diffuse(random_structure(30, 7), seed=3, packet_loss=0.05, packet_corruption=0.05,
                     latency_jitter_s=0.03)
    assert world.counters.corrupted > 0
    genuine = sorted(m for _, m, kind, detail in world.events if kind == "program" and detail["id"] == 1)
    assert genuine == sorted(world.structure.modules)


@pytest.mark.parametrize("name", shipped_names())
def test_shipped_configs_learn_their_true_frames(name: str) -> None:
    _assert_reached_once_with_true_frames(_diffuse(load_config(name)))


@pytest.mark.parametrize("loss", [0.0, 0.1])
def test_cyclic_car_runs_nothing_twice(loss: float) -> None:
    world = _diffuse(load_config("car8-cyclic"), seed=5, packet_loss=loss)
    _assert_reached_once_with_true_frames(world)
    assert sum(r.duplicates for r in world.runtimes.values()) > 0  # copies did come round the cycle
    programs = [e for e in world.events if e[2] == "program"]
    assert sorted(e[1] for e in programs) == sorted(world.structure.modules)


def test_report_is_json() -> None:
    report = json.loads(json.dumps(_diffuse(load_config("car7")).report()))
    assert len(report["modules"]) == 7 and all(m["frame_correct"] for m in report["modules"])
    assert report["links"]["delivered"] > 0


def test_same_seed_same_run() -> None:
    def run(seed: int) -> tuple:
        world = _diffuse(random_structure(25, 1), seed=seed, packet_loss=0.2)
        return world.now(), world.counters.as_dict(), [(t, m, k) for t, m, k, _ in world.events]
    assert run(4) == run(4)
    assert run(4) != run(5)


ROLE_BY_AXIS = assemble("""
    CENTER_POSITION_EW
    IF_FALSE_GOTO done
    SET_ROLE_NOTIFY 1
done:
    MIGRATE_CONTINUE
""")


def test_roles_and_notifications() -> None:
    table = RoleTable({1: "Sideways"}, {})
    world = LatticeWorld(load_config("car7"), table, latency_s=0.001)
    world.inject(ROLE_BY_AXIS)
    assert world.run_until_quiet(10)
    roles = world.roles_by_name()
    for mid, spec in world.structure.modules.items():
        assert roles[mid] == ("Sideways" if spec.axis == 1 else None)
    axle = world.runtimes[1]  # (0, 1, -1), two wheels below it
    assert sorted(axle.neighbour_roles) == [0] * 6 + [1, 1]
    assert sorted(m for _, m, kind, _ in world.events if kind == "role") == [3, 4, 5, 6]


def test_joint_takes_time() -> None:
    code = assemble("""
        EVAL_COMMAND ROTATE_CW 1
        SLEEP_ROTATIONS 1
        SET_LED 7
        EVAL_COMMAND ROTATE_TO 9
        END_TERMINATE
    """)
    world = LatticeWorld(load_config("snake1"), EMPTY)
    world.inject(code)
    hal = world.hals[0]
    world.advance(5.9)
    assert hal.led == 0 and hal.is_turning() and 0.95 < hal.joint_turns() < 1.0
    world.advance(0.2)
    assert hal.led == 7 and hal.is_turning()  # now turning towards 90 degrees
    world.advance(2.0)
    assert not hal.is_turning() and hal.joint_angle_deg() == pytest.approx(90.0)
    assert hal.joint_turns() == pytest.approx(1.25, abs=0.02)


def test_joint_speeds_and_directions() -> None:
    world = LatticeWorld(load_config("snake1"), EMPTY, joint_speed_turns_per_s=0.5)
    hal = world.hals[0]
    hal.rotate_continuously(-2)
    world.advance(0.25)
    assert hal.joint_turns() == pytest.approx(0.25) and hal.joint_angle_deg() == pytest.approx(-90.0)
    hal.rotate_by(-450)  # 2.5 s at speed 1
    world.advance(2.4)
    assert hal.is_turning()
    world.advance(0.2)
    assert not hal.is_turning() and hal.joint_angle_deg() == pytest.approx(-180.0)
    assert hal.joint_turns() == pytest.approx(1.5)
    hal.rotate_to(170)  # shorter way from 180 is 10 degrees back
    world.advance(0.1)
    assert not hal.is_turning() and hal.joint_angle_deg() == pytest.approx(170.0)
    hal.rotate_continuously(1)
    hal.stop_joint()
    assert not hal.is_turning()


def test_proximity_sees_obstacle_cells_on_free_connectors() -> None:
    structure = load_config("car7")
    front_left = 3  # LeftWheel at (1, 1, -2); sensor 1 faces (-1, +1, 0)
    assert structure.physical_direction(front_left, 1) == (-1, 1, 0)
    world = LatticeWorld(structure, EMPTY, obstacles=frozenset({(-1, 3, -2)}))
    hal = world.hals[front_left]
    assert hal.proximity(1) and not hal.proximity(5)
    world.set_obstacles(frozenset({(-2, 4, -2)}))  # three steps out: out of range
    assert not hal.proximity(1)
    port = next(iter(structure.connected_channels(front_left)))
    world.set_obstacles(frozenset({(0, 1, -1), (-1, 2, 0)}))  # where the axle is: connector busy
    assert not hal.proximity(port)


def test_modules_can_be_visible() -> None:
    structure = load_config("car17-wide")
    # wheel 3 at (1, 1, -2): its free connector towards (+1, 0, +1) sees the bridge EW (3, 1, 0)
    sensor = next(p for p in range(8) if structure.physical_direction(3, p) == (1, 0, 1))
    assert not LatticeWorld(structure, EMPTY).hals[3].proximity(sensor)
    assert LatticeWorld(structure, EMPTY, modules_visible=True).hals[3].proximity(sensor)


def test_handler_fires_on_obstacle() -> None:
    code = assemble("""
        HANDLE_EVENT EVENT_PROXIMITY_1 handler end-handler
        END_TERMINATE
    handler:
        SET_LED 3
        END_TERMINATE
    end:
    """)
    world = LatticeWorld(load_config("car7"), EMPTY)
    world.runtimes[3].inject(code)  # not the entry: inject gives it the frame of the origin
    world.advance(0.5)
    assert world.hals[3].led == 0
    world.set_obstacles(frozenset({(0, 2, -2)}))
    world.advance(0.1)
    assert world.hals[3].led == 3
    assert [k for _, m, k, _ in world.events if m == 3] == ["program", "handler"]


def test_idle_world_jumps_ahead() -> None:
    world = _diffuse(random_structure(10, 0))
    start, sent = world.now(), world.counters.sent
    world.hals[3].rotate_continuously(1)
    world.advance(3600.0)  # one jump, not 360 000 ticks
    assert world.now() == pytest.approx(start + 3600.0) and world.counters.sent == sent
    assert world.hals[3].joint_turns() == pytest.approx(600.0)
