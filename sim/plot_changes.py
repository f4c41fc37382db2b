"""What the plot says of a structure that changed (sim/plot.py): the changes it marks on the path
and the line under the picture that lists them."""

from __future__ import annotations

from typing import Any

# the structure's changes the plot marks: kind -> (marker, colour, legend label)
CHANGE_MARKS = {
    "connect": ("s", "seagreen", "latched"), "disconnect": ("s", "white", "unlatched"),
    "rotation_end": ("D", "seagreen", "quarter turn done"), "attach": ("P", "seagreen", "module attached"),
    "detach": ("X", "black", "module detached"), "outside": ("X", "black", "outside change"),
    "split": ("X", "orange", "robot split"),
    "rotation_failed": ("x", "red", "change failed"), "connect_failed": ("x", "red", "change failed"),
    "disconnect_failed": ("x", "red", "change failed"), "outside_failed": ("x", "red", "change failed"),
}
CHANGES_LISTED = 6  # in the line under the picture; the rest are counted


def structure_changes(report: dict[str, Any]) -> list[tuple[float, str, str]]:
    """(time, kind, words) of each change the plot marks, and each outside change as given."""
    out = []
    for e in report.get("events", []):
        kind, d, m = e["kind"], e.get("detail") or {}, e["module"]
        if kind == "outside":
            given = str(d.get("change", f"outside change of {m}"))  # '20s:detach 3': the time is said
            out.append((e["t"], kind, given.split(":", 1)[1].strip() if ":" in given else given))
        elif kind == "detach":
            out.append((e["t"], kind, f"detach {m}"))
        elif kind == "attach":
            out.append((e["t"], kind, f"attach {m}"))
        elif kind == "rotation_end":
            q = d.get("quarters")
            out.append((e["t"], kind, f"{m} turned {q:+}" if isinstance(q, int) else f"{m} turned"))
        elif kind in ("connect", "disconnect"):
            link = d.get("link")
            pair = f"{link[0]}.{link[1]}-{link[2]}.{link[3]}" if link else f"{m}"
            out.append((e["t"], kind, f"{'latch' if kind == 'connect' else 'unlatch'} {pair}"))
        elif kind == "split":
            parts = " | ".join(",".join(map(str, p)) for p in d.get("parts", []))
            out.append((e["t"], kind, f"split {parts}"))
        elif kind.endswith("_failed"):
            out.append((e["t"], kind, f"{m} {kind.replace('_', ' ')}"))
    return out


def changes_text(changes: list[tuple[float, str, str]]) -> str:
    """'structure changes: 20 s: detach 3 · 21.5 s: 1 turned +1 · ...' for the line under the picture."""
    shown = [f"{t:g} s: {words}" for t, kind, words in changes if kind != "detach"][:CHANGES_LISTED]
    rest = len([c for c in changes if c[1] != "detach"]) - len(shown)
    return "structure changes: " + " · ".join(shown) + (f" · +{rest} more" if rest > 0 else "")
