"""Judge a report against spec/atron.md "What the obstacle program works means"."""

from __future__ import annotations

import math
from typing import Any

from sim.report import heading_change
from vm.lattice.structure import Structure

MIN_TURN_DEG = 15.0
STRAIGHT_MAX_DEG = 5.0
FORWARD_MIN_M = 0.3  # the car must have driven at least this far towards +y before reacting
END_WINDOW_S = 4.0  # "drives forward again": judged over this many seconds
SETTLE_S = 2.0  # after the last wheel leaves Reverse, the axles straighten
MAX_MANOEUVRE_S = 40.0  # 3 wheel turns take 18 s unloaded; a wheel still reversing after this is stuck


def _is_reverse(role: str | None) -> bool:
    return (role or "").startswith("Reverse")


def reverse_spans(report: dict[str, Any]) -> list[tuple[float, float | None]]:
    """Manoeuvres: (first wheel enters Reverse, last wheel leaves it or None if still reversing)."""
    changes = sorted((t, m["id"], role) for m in report["modules"] for t, role in m["role_history"])
    reversing: set[int] = set()
    spans: list[tuple[float, float | None]] = []
    start: float | None = None
    for t, mid, role in changes:
        if _is_reverse(role):
            if not reversing:
                start = t
            reversing.add(mid)
        elif mid in reversing:
            reversing.discard(mid)
            if not reversing and start is not None:
                spans.append((start, t))
                start = None
    if reversing and start is not None:
        spans.append((start, None))
    return spans


def final_roles_ok(report: dict[str, Any], structure: Structure) -> bool:
    """Every module ends in its expected role, a Reverse mixin on it counting as that role."""
    expected = structure.expected_roles
    for m in report["modules"]:
        if m["id"] not in expected:
            continue
        role = m["final_role"]
        if _is_reverse(role) and "@" in role:
            role = role.split("@", 1)[1]
        if role != expected[m["id"]]:
            return False
    return True


def no_reverse_left(report: dict[str, Any]) -> bool:
    """Every manoeuvre ends within MAX_MANOEUVRE_S; one still running at the end must be younger."""
    end = report["duration_s"]
    return all((stop if stop is not None else end) - start <= MAX_MANOEUVRE_S
               for start, stop in reverse_spans(report))


def drove_forward(report: dict[str, Any]) -> bool:
    traj = report["trajectory"]
    return bool(traj) and max(p[2] for p in traj) - traj[0][2] >= FORWARD_MIN_M


def _window(traj: list[list[float]], t0: float, t1: float) -> list[list[float]]:
    return [p for p in traj if t0 <= p[0] <= t1]


def moves_forward(traj: list[list[float]], t0: float, t1: float) -> bool:
    """Between t0 and t1 the centre moves at least 5 cm along the car's own heading."""
    pts = _window(traj, t0, t1)
    if len(pts) < 2:
        return False
    a, b = pts[0], pts[-1]
    h = math.radians(b[3])
    return (b[1] - a[1]) * -math.sin(h) + (b[2] - a[2]) * math.cos(h) > 0.05


def forward_at_end(report: dict[str, Any]) -> bool:
    """Over the last seconds the centre moves along the car's own heading."""
    traj = report["trajectory"]
    return bool(traj) and moves_forward(traj, traj[-1][0] - END_WINDOW_S, traj[-1][0])


def first_manoeuvre(report: dict[str, Any]) -> tuple[float, float] | None:
    spans = reverse_spans(report)
    if not spans or spans[0][1] is None:
        return None
    return spans[0]  # type: ignore[return-value]


def judge_obstacle(report: dict[str, Any], structure: Structure) -> dict[str, bool]:
    """The first manoeuvre is judged in full: a wide car that turns little meets the wall again
    and may be reversing when the run ends, which is not a failure while it is short."""
    traj = report["trajectory"]
    first = first_manoeuvre(report)
    turned = again = False
    if first and traj:
        after = _window(traj, first[1], first[1] + SETTLE_S)
        turned = bool(after) and abs(heading_change([traj[0], after[-1]]) or 0.0) >= MIN_TURN_DEG
        again = moves_forward(traj, first[1], first[1] + SETTLE_S + END_WINDOW_S)
    return {
        "roles": final_roles_ok(report, structure),
        "detected": report["obstacle_detections"] >= 1,
        "no_collision": report["collided"] is False,
        "drove_forward": drove_forward(report),
        "turned": turned,
        "forward_again": again,
        "no_reverse_left": no_reverse_left(report),
    }


def judge_straight(report: dict[str, Any], structure: Structure) -> dict[str, bool]:
    turn = heading_change(report["trajectory"]) or 0.0
    return {
        "roles": final_roles_ok(report, structure),
        "drove_forward": drove_forward(report),
        "straight": abs(turn) < STRAIGHT_MAX_DEG,
        "no_detection": report["obstacle_detections"] == 0,
    }
