"""The report's account of a structure that changed (docs/simulator.md "Structures that change"):
each module's final cell and orientation, the final connections, and one summary line of what
changed. The events themselves are in the report's ``events`` (kinds in ``CHANGE_KINDS``)."""

from __future__ import annotations

from collections import Counter
from typing import Any

from vm.lattice.structure import AXIS_NAMES, Structure

CHANGE_KINDS = ("connect", "disconnect", "connect_failed", "disconnect_failed", "rotation_start",
                "rotation_end", "rotation_failed", "split", "outside", "outside_failed", "attach",
                "detach", "joint_unmodelled")


def module_fields(final: Structure, mid: int) -> dict[str, Any]:
    spec = final.modules.get(mid)
    if spec is None:  # taken away by an outside change
        return {"final_lattice": None, "final_orientation": None, "final_mount": None}
    return {"final_lattice": list(spec.position), "final_orientation": AXIS_NAMES[spec.axis],
            "final_mount": {**spec.mount.to_json(), "joint_quarters": spec.joint}}


def report_fields(final: Structure, events: list[dict[str, Any]]) -> dict[str, Any]:
    return {"connections": [[k.a, k.a_physical, k.b, k.b_physical] for k in final.links()],
            "parts": [sorted(p) for p in final.parts()],
            "structure_changes": dict(sorted(Counter(e["kind"] for e in events
                                                     if e["kind"] in CHANGE_KINDS).items()))}


def summary_line(report: dict[str, Any]) -> str | None:
    """'structure: 1 latched, 1 turn done, 1 split, 1 outside change (20s:detach 3); now 2 parts',
    or None when nothing changed."""
    counts = report.get("structure_changes") or {}
    if not counts:
        return None
    words = []
    for kind, one, many in (("connect", "latched", "latched"), ("disconnect", "unlatched", "unlatched"),
                            ("rotation_end", "turn done", "turns done"),
                            ("rotation_failed", "turn failed", "turns failed"),
                            ("connect_failed", "latch failed", "latches failed"),
                            ("disconnect_failed", "unlatch failed", "unlatches failed"),
                            ("split", "split", "splits"), ("outside", "outside change", "outside changes"),
                            ("outside_failed", "outside change failed", "outside changes failed"),
                            ("joint_unmodelled", "joint turned without moving the structure",
                             "joints turned without moving the structure")):
        n = counts.get(kind)
        if n:
            words.append(f"{n} {one if n == 1 else many}{_outside(report) if kind == 'outside' else ''}")
    parts = len(report.get("parts") or [1])
    return "structure: " + (", ".join(words) or "no change") + (f"; now {parts} parts" if parts > 1 else "")


def roles_line(report: dict[str, Any]) -> str | None:
    """What the outside changes did to roles: 'roles after the outside changes: module 3 LeftWheel →
    none, ...; 1 taken away; roles settled 1.02 s after the last change', or None without any.
    A module's role before is its role at the first change; modules taken away are not counted
    (their runtime stopped with them)."""
    outside = [e["t"] for e in report["events"] if e["kind"] == "outside"]
    if not outside:
        return None
    first, last = min(outside), max(outside)
    changed, gone, settled = [], 0, None
    for m in report["modules"]:
        history = m.get("role_history") or []
        if m.get("final_lattice") is None and "final_lattice" in m:
            gone += 1
            continue
        before = None
        for t, role in history:
            if t <= first:
                before = role
        if before != m["final_role"]:
            changed.append(f"module {m['id']} {before or 'none'} → {m['final_role'] or 'none'}")
        later = [t for t, _ in history if t > last]
        if later:
            settled = max(settled or 0.0, max(later) - last)
    words = ", ".join(changed) if changed else "every module kept its role"
    if gone:
        words += f"; {gone} taken away"
    if settled is not None:
        words += f"; roles settled {settled:.2f} s after the last change"
    return "roles after the outside changes: " + words


def _outside(report: dict[str, Any], shown: int = 3) -> str:
    """' (20s:detach 3, 25:stop 5)': the outside changes as they were given, the first few."""
    texts = [str((e.get("detail") or {}).get("change", "")) for e in report.get("events", [])
             if e.get("kind") == "outside"]
    texts = [t for t in texts if t]
    if not texts:
        return ""
    more = f", +{len(texts) - shown} more" if len(texts) > shown else ""
    return " (" + ", ".join(texts[:shown]) + more + ")"
