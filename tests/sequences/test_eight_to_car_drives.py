"""examples/eight_to_car.rdcd after its 23 steps (issue 24): the car's roles are found only once the
sequence is done, nothing of the car acts before, and the car drives and turns away from a wall as
examples/obstacle_avoidance.rdcd does on car7 (sim/scenario.py's judge, tests/sim)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import Options, simulate
from sim.scenario import MIN_TURN_DEG, forward_at_end, no_reverse_left, reverse_spans, turn_deg

EXAMPLE = (Path(__file__).resolve().parents[2] / "examples" / "eight_to_car.rdcd").read_text()
CAR_ROLES = ("Axle", "LeftWheel", "RightWheel", "Reverse@LeftWheel", "Reverse@RightWheel", "Go@Piece")
JOINT_COMMANDS = {1, 2, 3, 4, 5}  # ROTATE_CW, ROTATE_CCW, STOP, ROTATE_DEGREES, ROTATE_TO
ROTATE_TO = 5


def _run(world: str, obstacle: str, duration: float) -> dict[str, Any]:
    result = check_text(EXAMPLE)
    program = compile_model(result.model, text=EXAMPLE)
    assert not program.has_errors
    return simulate(program, load_config("eight7"),
                    Options(world=world, config="eight7", obstacle=obstacle, duration=duration))


def _done_at(report: dict[str, Any]) -> float:
    """When the first module heard that the 23rd step was done (a report keeps the last changes of
    each module's state, and the progress no longer changes after that one)."""
    return min(t for m in report["modules"] for t, name, v in m["state_history"]
               if name == "eightToCar" and v == 23)


def _net(traj: list[list[float]], t0: float, t1: float) -> float:
    pts = [p for p in traj if t0 <= p[0] <= t1]
    return math.dist(pts[0][1:3], pts[-1][1:3])


def test_in_the_lattice_world_nothing_of_the_car_acts_before_the_sequence_is_done() -> None:
    report = _run("lattice", "none", 60)
    done = _done_at(report)
    for m in report["modules"]:
        # every module plays Piece (and relays the progress) until the last step is done
        assert all(role == "Piece" for t, role in m["role_history"] if t < done), m["id"]
        assert m["final_role"] in CAR_ROLES, m["id"]
    early = [e for e in report["events"] if e["t"] < done and (
        e["kind"] == "command" and e["detail"]["command"] in JOINT_COMMANDS or e["kind"] == "handler")]
    assert early == []  # no wheel turns, no axle steers, no sensor is handled before it
    late = {e["detail"]["command"] for e in report["events"] if e["t"] >= done and e["kind"] == "command"}
    assert {1, 2} <= late  # then the wheels turn both ways (left and right)


@pytest.fixture(scope="module")
def wall() -> dict[str, Any]:
    return _run("physics", "wall:0.6", 100)


def test_in_the_physics_world_the_car_meets_the_wall_and_turns_away(wall: dict[str, Any]) -> None:
    done = _done_at(wall)
    roles = sorted(m["final_role"] for m in wall["modules"])
    assert roles == ["Axle", "Axle", "Go@Piece", "LeftWheel", "LeftWheel", "RightWheel", "RightWheel"]
    spans = reverse_spans(wall)
    assert spans and spans[0][0] > done  # the front wheels saw the wall after it started driving
    assert wall["obstacle_detections"] >= 1 and wall["collided"] is False
    turn = turn_deg(wall)
    assert turn is not None and abs(turn) >= MIN_TURN_DEG
    assert no_reverse_left(wall) and forward_at_end(wall)


def test_in_the_physics_world_both_axles_steer_while_the_wheels_reverse(wall: dict[str, Any]) -> None:
    """obstacle_avoidance's axles: the front one (module 6, y = 0 in the eight) from 90 to 60
    degrees, the rear one (module 1, at 0 after its last quarter turn) to 10, and both back."""
    start, end = reverse_spans(wall)[0]
    assert end is not None
    angles: dict[int, list[tuple[float, int]]] = {}
    for e in wall["events"]:
        if e["kind"] == "command" and e["detail"]["command"] == ROTATE_TO:
            angles.setdefault(e["module"], []).append((e["t"], 10 * e["detail"]["arg"]))
    assert set(angles) == {1, 6}  # the two axles, nothing else steers
    for module, rest, steered in ((6, 90, 60), (1, 0, 10)):
        before = [a for t, a in angles[module] if t < start]
        during = [a for t, a in angles[module] if start <= t <= end]
        assert before and set(before) == {rest}, (module, angles[module])
        assert during and during[0] == steered, (module, angles[module])  # while its wheel reverses
        assert angles[module][-1][1] == rest, (module, angles[module])  # then straight again


def test_in_the_physics_world_the_car_drives_after_the_sequence() -> None:
    report = _run("physics", "none", 90)
    done = _done_at(report)
    assert _net(report["trajectory"], done, done + 60) > 0.5
    assert report["obstacle_detections"] == 0
