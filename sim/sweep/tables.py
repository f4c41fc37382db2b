"""Tables regenerated from the rows: runs.csv (and runs.parquet), summary.csv per grid cell.

Rows are read back one at a time in grid order, so a table of 10,000 runs costs no more memory
than one of ten; only the per-cell counts are held.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO

from rdcd_core.outputs import write_with
from sim.sweep.plan import Plan
from sim.sweep.rows import columns, criteria, failures, succeeded
from sim.sweep.store import replace_with

Z95 = 1.959963984540054


def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion (0, 1 for no trials)."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def rows(plan: Plan) -> Iterator[dict[str, Any]]:
    """The finished rows of the plan's runs, in grid order, each with its verdict ``success``."""
    e = plan.experiment
    for key in plan.keys():
        row = plan.store.read(key)
        if row is None:
            continue
        row["success"] = succeeded(row, e.checks, e.min_turn_deg, e.bounds, e.state, e.held_by, e.structure)
        yield row


FAILED_PREFIX = "failed_"  # summary.csv: failed_<criterion> = completed runs of the cell that missed it


@dataclass
class Cell:
    values: dict[str, Any]
    criteria: list[str]
    runs: int = 0
    ok: int = 0
    successes: int = 0
    missed: dict[str, int] = field(default_factory=dict)

    def as_row(self) -> dict[str, Any]:
        low, high = wilson(self.successes, self.ok)
        rate = self.successes / self.ok if self.ok else None
        return {**self.values, "runs": self.runs, "completed": self.ok, "failed": self.runs - self.ok,
                "successes": self.successes, "success_rate": rate, "ci95_low": low, "ci95_high": high,
                **{f"{FAILED_PREFIX}{name}": self.missed.get(name, 0) for name in self.criteria}}


def summary(plan: Plan) -> list[dict[str, Any]]:
    """One row per grid cell (the grid's axes but the seed): runs, successes, rate and Wilson 95 %,
    and for each success criterion how many completed runs missed it (``failed_<name>``: a run
    that misses two counts in both). The rate counts completed runs; runs that failed (crashed,
    timed out) are counted apart."""
    e = plan.experiment
    names = criteria(e.checks, e.bounds, e.state, e.held_by, e.structure)
    cells: dict[tuple, Cell] = {}
    axes = e.cell_axes
    for row in rows(plan):
        values = {a: row.get(a) for a in axes}
        cell = cells.setdefault(tuple(values.values()), Cell(values, names))
        cell.runs += 1
        if row["status"] == "ok":
            cell.ok += 1
            cell.successes += bool(row["success"])
            for name in failures(row, e.checks, e.min_turn_deg, e.bounds, e.state, e.held_by,
                                 e.structure):
                cell.missed[name] = cell.missed.get(name, 0) + 1
    return [cell.as_row() for cell in cells.values()]


def missed_text(cell: dict[str, Any]) -> str:
    """What the completed runs of a summary row missed: "forward_again 2, turned 1" ("" if none)."""
    counts = [(name[len(FAILED_PREFIX):], n) for name, n in cell.items()
              if name.startswith(FAILED_PREFIX) and n]
    return ", ".join(f"{name} {n}" for name, n in sorted(counts, key=lambda c: -c[1]))


def write_runs_csv(plan: Plan) -> Path:
    path = plan.store.root / "runs.csv"
    names = columns(plan.experiment.option_names)

    def write(file: BinaryIO) -> None:
        with _Utf8Text(file) as text:
            writer = csv.DictWriter(text, names, extrasaction="ignore")
            writer.writeheader()
            for row in rows(plan):
                writer.writerow(row)
    write_with(str(path), write)
    return path


def write_parquet(plan: Plan) -> Path | None:
    """runs.parquet when pyarrow is installed (``pip install 'rdcd[parquet]'``), in batches."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return None
    path = plan.store.root / "runs.parquet"
    names = columns(plan.experiment.option_names)
    schema = pa.schema([(n, _arrow_type(pa, n, plan)) for n in names])

    def write(temporary: str) -> None:
        with pq.ParquetWriter(temporary, schema) as writer:
            batch: list[dict[str, Any]] = []
            for row in rows(plan):
                batch.append({n: row.get(n) for n in names})
                if len(batch) == 1000:
                    writer.write_table(pa.Table.from_pylist(batch, schema))
                    batch = []
            if batch:
                writer.write_table(pa.Table.from_pylist(batch, schema))
    replace_with(path, write)
    return path


def _arrow_type(pa: Any, name: str, plan: Plan) -> Any:
    from sim.sweep.options import sweepable
    from sim.sweep.rows import METRICS

    spec = sweepable().get(name)
    if spec is not None:
        return {int: pa.int64(), float: pa.float64()}.get(spec.kind, pa.string())
    if name == "success" or name.startswith("check_") or name == "collided":
        return pa.bool_()
    if name in METRICS:
        counts = ("detections", "messages_sent", "messages_delivered", "messages_dropped", "runtime_errors",
                  "unsettled_states")
        return pa.int64() if name in counts else pa.float64()
    return pa.string()


def write_summary_csv(plan: Plan, cells: list[dict[str, Any]]) -> Path:
    path = plan.store.root / "summary.csv"
    e = plan.experiment
    missed = criteria(e.checks, e.bounds, e.state, e.held_by, e.structure)
    names = list(cells[0]) if cells else [*e.cell_axes, "runs", "completed", "failed", "successes",
                                          "success_rate", "ci95_low", "ci95_high",
                                          *(f"{FAILED_PREFIX}{n}" for n in missed)]

    def write(file: BinaryIO) -> None:
        with _Utf8Text(file) as text:
            writer = csv.DictWriter(text, names)
            writer.writeheader()
            writer.writerows(cells)
    write_with(str(path), write)
    return path


def summary_text(plan: Plan, cells: list[dict[str, Any]]) -> str:
    """The summary as a plain-text table for the terminal (and the report)."""
    axes = plan.experiment.cell_axes
    head = [*axes, "runs", "failed", "success", "rate", "95% interval", "missed (runs)"]
    body = []
    for c in cells:
        rate = "-" if c["success_rate"] is None else f"{100 * c['success_rate']:.0f}%"
        interval = ("-" if c["success_rate"] is None
                    else f"{100 * c['ci95_low']:.0f}-{100 * c['ci95_high']:.0f}%")
        body.append([*(_text(c[a]) or "none" for a in axes), str(c["runs"]), str(c["failed"]),
                     f"{c['successes']}/{c['completed']}", rate, interval, missed_text(c) or "-"])
    widths = [max(len(r[i]) for r in [head, *body]) for i in range(len(head))]
    last = len(head) - 1  # the missed checks: text, left-aligned like the axes

    def cell(i: int, v: str, w: int) -> str:
        return v.ljust(w) if i < len(axes) or i == last else v.rjust(w)
    lines = ["  ".join(cell(i, v, w) for i, (v, w) in enumerate(zip(r, widths, strict=True))).rstrip()
             for r in [head, *body]]
    return "\n".join(lines)


def _text(value: Any) -> str:
    from sim.sweep.options import number_text

    return number_text(value) if isinstance(value, float) else str(value)


class _Utf8Text(io.TextIOWrapper):
    """UTF-8 text over the binary file ``write_with`` hands out, left open for it to sync and close."""

    def __init__(self, file: BinaryIO) -> None:
        super().__init__(file, encoding="utf-8", newline="")

    def __exit__(self, *exc: object) -> None:
        self.flush()
        self.detach()
