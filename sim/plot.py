"""Top view of a run: path, obstacles, detections, reversals, modules coloured by final role, and
what changed in the structure (markers on the path at the times of its changes, and a line under
the picture listing them: docs/simulator.md "Structures that change")."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, Rectangle  # noqa: E402

from rdcd_core.outputs import write_with  # noqa: E402
from sim import params  # noqa: E402
from sim.geometry import lattice_to_world  # noqa: E402
from sim.plot_changes import CHANGE_MARKS, changes_text, structure_changes  # noqa: E402
from sim.report import heading_change  # noqa: E402
from sim.scenario import reverse_spans  # noqa: E402
from vm.lattice.structure import Structure  # noqa: E402

ROLE_COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive",
                "tab:cyan"]


def _point_at(trajectory: list[list[float]], t: float) -> tuple[float, float] | None:
    best = min(trajectory, key=lambda p: abs(p[0] - t), default=None)
    return (best[1], best[2]) if best else None


def _rotate(dx: float, dy: float, heading_deg: float) -> tuple[float, float]:
    h = math.radians(heading_deg)
    return dx * math.cos(h) - dy * math.sin(h), dx * math.sin(h) + dy * math.cos(h)


def _mark_changes(ax: Any, traj: list[list[float]], changes: list[tuple[float, str, str]]) -> None:
    labelled = set()
    for t, kind, _ in changes:
        if kind not in CHANGE_MARKS or not traj:
            continue
        marker, colour, label = CHANGE_MARKS[kind]
        p = _point_at(traj, t)
        ax.scatter([p[0]], [p[1]], marker=marker, s=70, color=colour, edgecolor="black", linewidth=0.7,
                   zorder=8, label=None if label in labelled else label)
        labelled.add(label)


def _draw_car(ax: Any, report: dict[str, Any], pose: list[float], colours: dict[str | None, str],
              alpha: float, at_end: bool = False) -> None:
    """The modules at a pose of the trajectory (the robot is drawn rigid, joints at rest). At the
    start, modules attached later are left out; at the end, modules taken away, and a module that
    moved is drawn on its final cell."""
    start = report["trajectory"][0]
    cx0, cy0 = start[1], start[2]
    attached = {e["module"] for e in report.get("events", []) if e["kind"] == "attach"}
    for m in report["modules"]:
        gone = at_end and "final_lattice" in m and m["final_lattice"] is None
        if gone or (not at_end and m["id"] in attached):
            continue
        xy0 = report.get("module_start_xy", {}).get(str(m["id"])) or lattice_to_world(m["lattice"])
        x, y = xy0[0] - cx0, xy0[1] - cy0
        if at_end and m.get("final_lattice") and m["final_lattice"] != m["lattice"]:  # moved to another cell
            a, b = lattice_to_world(m["final_lattice"]), lattice_to_world(m["lattice"])
            x, y = x + a[0] - b[0], y + a[1] - b[1]
        dx, dy = _rotate(x, y, pose[3] - start[3])
        ax.add_patch(Circle((pose[1] + dx, pose[2] + dy), params.MODULE_RADIUS, alpha=alpha,
                            facecolor=colours[m["final_role"]], edgecolor="black", linewidth=0.4, zorder=3))


def plot_report(report: dict[str, Any], structure: Structure | None, path: str) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 6.0), dpi=80)
    roles = sorted({m["final_role"] for m in report["modules"]}, key=lambda r: (r is None, r or ""))
    colours = {r: ("lightgrey" if r is None else ROLE_COLOURS[i % len(ROLE_COLOURS)])
               for i, r in enumerate(roles)}
    for ob in report.get("obstacles", []):
        ax.add_patch(Rectangle((ob["x"] - ob["w"] / 2, ob["y"] - ob["l"] / 2), ob["w"], ob["l"],
                               facecolor="firebrick", alpha=0.6, label=f"obstacle ({ob['kind']})"))
    traj = report["trajectory"]
    if traj:
        _draw_car(ax, report, traj[0], colours, 0.35)
        _draw_car(ax, report, traj[-1], colours, 0.9, at_end=True)
        ax.plot([p[1] for p in traj], [p[2] for p in traj], color="black", linewidth=1.2,
                label="path (centre)", zorder=4)
        pts = [_point_at(traj, e["t"]) for e in report["events"] if e["kind"] == "handler"]
        if pts:
            ax.scatter([p[0] for p in pts], [p[1] for p in pts], marker="*", s=160, color="gold",
                       edgecolor="black", zorder=6, label="obstacle detected")
        for i, (start, stop) in enumerate(reverse_spans(report)):
            seg = [p for p in traj if start <= p[0] <= (stop if stop is not None else traj[-1][0])]
            ax.plot([p[1] for p in seg], [p[2] for p in seg], color="red", linewidth=2.2, zorder=4.5,
                    label="reversing (wheels in Reverse)" if i == 0 else None)
            if seg:
                ax.scatter([seg[0][1]], [seg[0][2]], marker="v", s=40, color="red", edgecolor="black",
                           zorder=7, label="reversal starts" if i == 0 else None)
        ax.scatter([traj[0][1]], [traj[0][2]], marker="o", color="green", zorder=5, label="start")
    changes = structure_changes(report)
    _mark_changes(ax, traj, changes)
    for role in roles:
        ax.scatter([], [], color=colours[role], edgecolor="black", s=60, label=f"role {role or 'none'}")
    turn = heading_change(traj)
    result = f"{report['obstacle_detections']} detection(s)"
    if report.get("collided") is not None:
        result += ", collided" if report["collided"] else ", no collision"
    turn_text = f", heading {turn:+.0f}°" if turn is not None else ""
    title = f"{report['config']} — {report['obstacle']}, {report['duration_s']:g} s: {result}{turn_text}"
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("x (m, east)")
    ax.set_ylabel("y (m, north)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize=7, framealpha=0.85)
    fig.tight_layout()
    if changes:  # what changed, under the picture (the lattice world has no path to mark it on)
        fig.subplots_adjust(bottom=0.14)
        fig.text(0.01, 0.01, changes_text(changes), fontsize=7, wrap=True)
    try:
        # the format named by the extension (checked by the command line), written atomically
        picture_format = Path(path).suffix[1:].lower() or "png"
        write_with(path, lambda file: fig.savefig(file, format=picture_format))
    finally:
        plt.close(fig)

