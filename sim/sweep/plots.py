"""The sweep's pictures and the index.html that shows them with the summary table.

Success rate against packet loss per configuration with its Wilson 95 % band; a configuration ×
obstacle heatmap of success rates; distributions of heading change and distance. Figures are
drawn with matplotlib's object API (no pyplot: a notebook's backend is left alone) and every file
is written to a temporary name and renamed into place.
"""

from __future__ import annotations

import html
from collections import defaultdict
from pathlib import Path
from typing import Any

from rdcd_core.outputs import write_atomically, write_with
from sim.sweep.plan import Plan
from sim.sweep.tables import missed_text, rows, wilson

LOSS_PLOT = "success_vs_packet_loss.png"
HEATMAP = "config_obstacle_heatmap.png"
DISTRIBUTIONS = "distributions.png"


def _save(fig: Any, path: Path) -> Path:
    write_with(str(path), lambda file: fig.savefig(file, format="png", dpi=100))
    return path


def write_plots(plan: Plan) -> list[Path]:
    from matplotlib.figure import Figure

    by_loss: dict[str, dict[float, list[int]]] = defaultdict(lambda: defaultdict(lambda: [0, 0]))
    by_pair: dict[tuple[str, str], list[int]] = defaultdict(lambda: [0, 0])
    measures: dict[str, dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for row in rows(plan):
        if row["status"] != "ok":
            continue
        counts = (int(row["success"]), 1)
        for target in (by_loss[row["config"]][row["packet_loss"]], by_pair[(row["config"], row["obstacle"])]):
            target[0] += counts[0]
            target[1] += counts[1]
        for name in ("heading_change_deg", "distance_m"):
            if row.get(name) is not None:
                measures[name][row["config"]].append(row[name])
    written = []
    if "packet_loss" in plan.experiment.grid.names and by_loss:
        written.append(_loss_plot(Figure(figsize=(6.4, 4.2)), by_loss, plan.store.root / LOSS_PLOT))
    if by_pair:
        written.append(_heatmap(Figure(figsize=(6.4, 4.2)), by_pair, plan.store.root / HEATMAP))
    if measures:
        written.append(_distributions(Figure(figsize=(9.6, 3.6)), measures, plan.store.root / DISTRIBUTIONS))
    return written


def _loss_plot(fig: Any, by_loss: dict[str, dict[float, list[int]]], path: Path) -> Path:
    ax = fig.add_subplot()
    everything = sorted({x for points in by_loss.values() for x in points})
    spacing = min((b - a for a, b in zip(everything, everything[1:], strict=False)), default=0.1)
    for i, (config, points) in enumerate(by_loss.items()):
        losses = sorted(points)
        # Configurations side by side around each loss, so that equal rates do not hide each other.
        shift = (i - (len(by_loss) - 1) / 2) * spacing * 0.06
        xs = [x + shift for x in losses]
        rates = [points[x][0] / points[x][1] for x in losses]
        bands = [wilson(*points[x]) for x in losses]
        line, = ax.plot(xs, rates, marker="osD^v<>"[i % 7], label=config)
        ax.fill_between(xs, [b[0] for b in bands], [b[1] for b in bands], color=line.get_color(), alpha=0.12)
    ax.set_xlabel("packet loss")
    ax.set_ylabel("success rate (band: Wilson 95 %)")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return _save(fig, path)


def _heatmap(fig: Any, by_pair: dict[tuple[str, str], list[int]], path: Path) -> Path:
    configs = list(dict.fromkeys(c for c, _ in by_pair))
    obstacles = list(dict.fromkeys(o for _, o in by_pair))
    grid = [[by_pair[(c, o)][0] / by_pair[(c, o)][1] if (c, o) in by_pair else float("nan")
             for o in obstacles] for c in configs]
    ax = fig.add_subplot()
    image = ax.imshow(grid, vmin=0, vmax=1, cmap="RdYlGn", aspect="auto")
    ax.set_xticks(range(len(obstacles)), obstacles)
    ax.set_yticks(range(len(configs)), configs)
    for i, c in enumerate(configs):
        for j, o in enumerate(obstacles):
            if (c, o) in by_pair:
                s, n = by_pair[(c, o)]
                ax.text(j, i, f"{100 * s / n:.0f}%\n{s}/{n}", ha="center", va="center", fontsize=9)
    ax.set_xlabel("obstacle")
    ax.set_ylabel("configuration")
    fig.colorbar(image, ax=ax, label="success rate")
    fig.tight_layout()
    return _save(fig, path)


def _distributions(fig: Any, measures: dict[str, dict[str, list[float]]], path: Path) -> Path:
    titles = {"heading_change_deg": "heading change (°)", "distance_m": "distance travelled (m)"}
    for i, name in enumerate(titles):
        ax = fig.add_subplot(1, 2, i + 1)
        every = [v for values in measures.get(name, {}).values() for v in values]
        low, high = (min(every), max(every)) if every else (0.0, 1.0)
        edges = [low + (high - low) * k / 30 for k in range(31)] if high > low else 10  # shared bins
        for config, values in measures.get(name, {}).items():
            ax.hist(values, bins=edges, alpha=0.5, label=config)
        ax.set_xlabel(titles[name])
        ax.set_ylabel("runs")
        if measures.get(name):
            ax.legend(fontsize=8)
    fig.tight_layout()
    return _save(fig, path)


def write_index(plan: Plan, cells: list[dict[str, Any]], images: list[Path], command: str) -> Path:

    e = plan.experiment
    axes = e.cell_axes
    head = "".join(f"<th>{html.escape(a)}</th>" for a in [*axes, "runs", "failed", "successes", "rate",
                                                          "95 % interval", "missed (runs)"])
    body = []
    for c in cells:
        rate = "-" if c["success_rate"] is None else f"{100 * c['success_rate']:.0f} %"
        ci = "-" if c["success_rate"] is None else f"{100 * c['ci95_low']:.0f}–{100 * c['ci95_high']:.0f} %"
        cols = [*(c[a] for a in axes), c["runs"], c["failed"], f"{c['successes']}/{c['completed']}", rate, ci,
                missed_text(c) or "–"]
        body.append("<tr>" + "".join(f"<td>{html.escape(str(v))}</td>" for v in cols) + "</tr>")
    criteria = ", ".join(e.checks) or "the run completes"
    if "turned" in e.checks:
        criteria += f" (turned ≥ {e.min_turn_deg:g}°)"
    for metric, (low, high) in e.bounds.items():
        criteria += f", {metric} in [{'' if low is None else low}, {'' if high is None else high}]"
    for check in (*e.state, *e.held_by, *e.structure):
        criteria += f", {check.describe()}"
    page = f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(e.title)}</title>
<style>body{{font-family:sans-serif;margin:2em;max-width:70em}}table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:.25em .6em;text-align:right}}th{{background:#eee}}
img{{max-width:100%;margin:1em 0}}code{{background:#f4f4f4;padding:.1em .3em}}</style></head><body>
<h1>{html.escape(e.title)}</h1>
<p>Program <code>{html.escape(plan.program)}</code>; {plan.total} runs over
{html.escape(' × '.join(e.grid.names))}. Success: {html.escape(criteria)}.
The rate is over completed runs; failed runs (crashed, timed out) are counted apart.
<em>Missed</em> counts, for each criterion, the completed runs of the cell that did not meet it
(a run that misses two is counted under both; summary.csv has them as <code>failed_NAME</code>).</p>
<p>Run again (only missing runs): <code>{html.escape(command)}</code></p>
<table><tr>{head}</tr>
{chr(10).join(body)}
</table>
<p><a href="runs.csv">runs.csv</a> (one row per run; its <code>simulate</code> column replays it)
· <a href="summary.csv">summary.csv</a></p>
{''.join(f'<p><img src="{html.escape(p.name)}" alt="{html.escape(p.stem)}"></p>' for p in images)}
</body></html>
"""
    path = plan.store.root / "index.html"
    write_atomically(str(path), page)
    return path
