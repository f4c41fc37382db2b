"""Judge a report against docs/simulator.md "What the obstacle program works means".

The judge is literal about the end of the run: when the run ends, no module's role is a Reverse
mixin application, and the car is driving forward along its own heading over the last
``END_WINDOW_S`` seconds. A car that meets the wall again and is still reversing when the run
ends fails, however short its second manoeuvre.
"""

from __future__ import annotations

import math
from typing import Any

from vm.lattice.joint import wrap
from vm.lattice.structure import Structure

MIN_TURN_DEG = 15.0
STRAIGHT_MAX_DEG = 5.0
FORWARD_MIN_M = 0.3  # the car must have driven at least this far towards +y before reacting
END_WINDOW_S = 4.0  # "drives forward again": judged over the last this many seconds
END_FORWARD_MIN_M = 0.1  # ... moving at least this far along its heading (0.24 m at full speed)


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
    """Every module ends in exactly its expected role (a Reverse mixin on it does not count)."""
    expected = structure.expected_roles
    return all(m["final_role"] == expected[m["id"]] for m in report["modules"] if m["id"] in expected)


def no_reverse_left(report: dict[str, Any]) -> bool:
    """No module's final role is a Reverse mixin application."""
    return not any(_is_reverse(m["final_role"]) for m in report["modules"])


def _window(traj: list[list[float]], t0: float, t1: float) -> list[list[float]]:
    return [p for p in traj if t0 <= p[0] <= t1]


def drove_forward(report: dict[str, Any]) -> bool:
    """Before the first manoeuvre (or in the whole run) the centre got FORWARD_MIN_M further along +y."""
    traj = report["trajectory"]
    spans = reverse_spans(report) if "modules" in report else []
    before = _window(traj, 0.0, spans[0][0]) if spans else traj
    return bool(before) and max(p[2] for p in before) - traj[0][2] >= FORWARD_MIN_M


def moves_forward(traj: list[list[float]], t0: float, t1: float, min_m: float = 0.05) -> bool:
    """Between t0 and t1 the centre moves at least ``min_m`` along the car's own heading."""
    pts = _window(traj, t0, t1)
    if len(pts) < 2:
        return False
    a, b = pts[0], pts[-1]
    h = math.radians(b[3])
    return (b[1] - a[1]) * -math.sin(h) + (b[2] - a[2]) * math.cos(h) >= min_m


def forward_at_end(report: dict[str, Any]) -> bool:
    """Over the last END_WINDOW_S seconds the centre moves END_FORWARD_MIN_M along the car's heading."""
    traj = report["trajectory"]
    return bool(traj) and moves_forward(traj, traj[-1][0] - END_WINDOW_S, traj[-1][0], END_FORWARD_MIN_M)


def turn_deg(report: dict[str, Any]) -> float | None:
    """Heading at the end of the run minus heading when the first manoeuvre began (-180..180).

    Measured from the first Reverse, not from t = 0, so that drift while the program spreads and
    the wheels start one by one is not counted as avoiding the obstacle.
    """
    traj = report["trajectory"]
    spans = reverse_spans(report)
    if not traj or not spans:
        return None
    before = _window(traj, 0.0, spans[0][0])
    return wrap(traj[-1][3] - (before[-1] if before else traj[0])[3])


def heading_deviation(traj: list[list[float]]) -> float:
    """Largest |heading - initial heading| over the run, in degrees (0 for an empty trajectory)."""
    return max((abs(wrap(p[3] - traj[0][3])) for p in traj), default=0.0)


def judge_obstacle(report: dict[str, Any], structure: Structure) -> dict[str, bool]:
    turn = turn_deg(report)
    return {
        "roles": final_roles_ok(report, structure),
        "detected": report["obstacle_detections"] >= 1,
        "no_collision": report["collided"] is False,
        "drove_forward": drove_forward(report),
        "turned": turn is not None and abs(turn) >= MIN_TURN_DEG,
        "forward_at_end": forward_at_end(report),
        "no_reverse_left": no_reverse_left(report),
    }


def judge_straight(report: dict[str, Any], structure: Structure) -> dict[str, bool]:
    """Largest heading deviation from the start, over the whole run, stays under STRAIGHT_MAX_DEG."""
    return {
        "roles": final_roles_ok(report, structure),
        "drove_forward": drove_forward(report),
        "straight": heading_deviation(report["trajectory"]) < STRAIGHT_MAX_DEG,
        "no_detection": report["obstacle_detections"] == 0,
    }
