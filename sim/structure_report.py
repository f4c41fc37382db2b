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
    """'structure: 2 connects, 1 rotation (1 failed), 1 split, ...; 2 parts', or None."""
    counts = report.get("structure_changes") or {}
    if not counts:
        return None
    words = []
    for kind, label in (("connect", "latched"), ("disconnect", "unlatched"), ("rotation_end", "turns done"),
                        ("rotation_failed", "turns failed"), ("connect_failed", "latches failed"),
                        ("disconnect_failed", "unlatches failed"), ("split", "splits"),
                        ("outside", "outside changes"), ("outside_failed", "outside changes failed"),
                        ("joint_unmodelled", "joints turned without moving the structure")):
        if counts.get(kind):
            words.append(f"{counts[kind]} {label}")
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
