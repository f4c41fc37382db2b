"""Words for the structure's events in the replay (kinds of sim/structure_report.py CHANGE_KINDS,
details as the worlds give them to ``on_change``)."""

from __future__ import annotations

from typing import Any


def describe_change(kind: str, detail: dict[str, Any]) -> str:
    """One line for a structure event of the world (sim/structure_report.py CHANGE_KINDS)."""
    link = detail.get("link")
    linked = f" (module {link[0]} connector {link[1]} – module {link[2]} connector {link[3]})" if link else ""
    connector = f" connector {detail['connector']}" if "connector" in detail else ""
    why = f": {detail['reason']}" if detail.get("reason") else ""
    carried = detail.get("carried") or []
    carrying = f", carrying {', '.join(map(str, carried))}" if carried else ""
    quarters = detail.get("quarters")
    turn = ""
    if isinstance(quarters, int):
        turn = f" {quarters:+d} quarter turn{'s' if abs(quarters) != 1 else ''}"
    if kind == "connect":
        return f"latched{connector}{linked}"
    if kind == "disconnect":
        return f"unlatched{connector}{linked}"
    if kind in ("connect_failed", "disconnect_failed"):
        return f"{'latch' if kind == 'connect_failed' else 'unlatch'}{connector} failed{why}"
    if kind == "rotation_start":
        return f"rotation{turn} starts ({detail.get('moving', '?')} hemisphere moves{carrying})"
    if kind == "rotation_end":
        return f"rotation{turn} done{carrying}"
    if kind == "rotation_failed":
        return f"rotation{turn} failed{why}"
    if kind == "split":
        return "the robot split into " + " | ".join(", ".join(map(str, p)) for p in detail.get("parts", []))
    if kind in ("outside", "outside_failed"):
        failed = " failed" if kind == "outside_failed" else ""
        return f"outside change {detail.get('change', '')}{failed}{why}"
    if kind == "attach":
        return f"attached{linked}"
    if kind == "detach":
        return "detached"
    return kind.replace("_", " ") + why
