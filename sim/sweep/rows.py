"""One row per run: its fields, how a report becomes a row, and how a row is judged.

A row keeps the measures and the named checks of the obstacle scenario (sim/scenario.py;
docs/simulator.md says what each means), not the verdict:
success is decided from the experiment's criteria when tables are written, so changing the
criteria needs no run again.
"""

from __future__ import annotations

from typing import Any

from sim import scenario
from sim.report import distance, heading_change
from sim.sweep import structure_checks
from sim.sweep.state_checks import HeldBy, StateCheck, facts, holds
from sim.sweep.structure_checks import StructureCheck
from vm.lattice.structure import Structure

# Named checks of the obstacle scenario; "turned" is judged from turn_deg against the experiment's angle.
CHECKS = ("roles", "detected", "no_collision", "drove_forward", "turned", "forward_again",
          "no_reverse_left", "straight", "no_detection")
STORED_CHECKS = tuple(c for c in CHECKS if c != "turned")
METRICS = ("detections", "collided", "min_obstacle_distance_m", "distance_m", "heading_change_deg",
           "turn_deg", "max_heading_deviation_deg", "messages_sent", "messages_delivered",
           "messages_dropped", "runtime_errors", "unsettled_states", "wall_time_s", "real_time_factor")
# Measures that depend on the machine, not on the run: left out when rows are compared.
MACHINE_FIELDS = ("wall_time_s", "real_time_factor", "host", "finished_at")


def columns(option_names: list[str]) -> list[str]:
    return (["key", "status", "success", "error", *option_names, *METRICS,
             *(f"check_{c}" for c in STORED_CHECKS), "simulate", "host", "finished_at"])


def measures(report: dict[str, Any], structure: Structure) -> dict[str, Any]:
    """The row's measures and checks from a ``rdcd simulate`` report."""
    traj = report["trajectory"]
    change = heading_change(traj)
    length = distance(traj)
    turn = scenario.turn_deg(report)
    straight = scenario.judge_straight(report, structure)
    obstacle = scenario.judge_obstacle(report, structure)
    row: dict[str, Any] = {
        "detections": report["obstacle_detections"],
        "collided": report["collided"],
        "min_obstacle_distance_m": report["min_obstacle_distance_m"],
        "distance_m": None if length is None else round(length, 4),
        "heading_change_deg": None if change is None else round(change, 3),
        "turn_deg": None if turn is None else round(turn, 3),
        "max_heading_deviation_deg": round(scenario.heading_deviation(traj), 3) if traj else None,
        "messages_sent": report["messages"]["sent"],
        "messages_delivered": report["messages"]["delivered"],
        "messages_dropped": report["messages"]["dropped"],
        "runtime_errors": sum(len(m["errors"]) for m in report["modules"]),
        "unsettled_states": len(report.get("unsettled", [])),
        "wall_time_s": report["wall_time_s"],
        "real_time_factor": report["real_time_factor"],
    }
    checks = {"roles": obstacle["roles"], "detected": obstacle["detected"],
              "no_collision": obstacle["no_collision"], "drove_forward": obstacle["drove_forward"],
              "forward_again": obstacle["forward_at_end"], "no_reverse_left": obstacle["no_reverse_left"],
              "straight": straight["straight"] if traj else False,
              "no_detection": straight["no_detection"]}
    row.update({f"check_{name}": bool(value) for name, value in checks.items()})
    # for [success.state], [success.held_by] and [success.structure]; not a column
    row["final"] = {**facts(report, structure), **structure_checks.facts(report)}
    return row


def succeeded(row: dict[str, Any], checks: tuple[str, ...], min_turn_deg: float,
              bounds: dict[str, tuple[float | None, float | None]], state: tuple[StateCheck, ...] = (),
              held_by: tuple[HeldBy, ...] = (), structure: tuple[StructureCheck, ...] = ()) -> bool:
    """The experiment's verdict on a row: it ran, every named check holds, every bound holds, every
    final-state and final-structure check holds."""
    return row.get("status") == "ok" and not failures(row, checks, min_turn_deg, bounds, state, held_by,
                                                      structure)


def criteria(checks: tuple[str, ...], bounds: dict[str, tuple[float | None, float | None]],
             state: tuple[StateCheck, ...] = (), held_by: tuple[HeldBy, ...] = (),
             structure: tuple[StructureCheck, ...] = ()) -> list[str]:
    """The names of an experiment's success criteria: its checks, then its bounded measures, then
    ``final_state`` when it tests final state or who holds a role, then one ``structure_KEY`` per
    key of [success.structure]."""
    names = [*checks, *(name for name in bounds if name not in checks)]
    if state or held_by:
        names.append("final_state")
    return [*names, *(check.criterion for check in structure)]


def failures(row: dict[str, Any], checks: tuple[str, ...], min_turn_deg: float,
             bounds: dict[str, tuple[float | None, float | None]], state: tuple[StateCheck, ...] = (),
             held_by: tuple[HeldBy, ...] = (), structure: tuple[StructureCheck, ...] = ()) -> list[str]:
    """The criteria (names as in ``criteria``) a completed run does not meet; [] for a success."""
    failed = []
    for name in checks:
        if name == "turned":
            turn = row.get("turn_deg")
            if turn is None or abs(turn) < min_turn_deg:
                failed.append(name)
        elif not row.get(f"check_{name}"):
            failed.append(name)
    for metric, (low, high) in bounds.items():
        value = row.get(metric)
        if (value is None or isinstance(value, str) or (low is not None and value < low)
                or (high is not None and value > high)):
            failed.append(metric)
    if (state or held_by) and not holds(row.get("final"), state, held_by):
        failed.append("final_state")
    return failed + structure_checks.failures(row.get("final"), structure)
