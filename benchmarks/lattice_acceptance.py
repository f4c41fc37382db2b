"""Acceptance of compiler + VM + lattice world on the obstacle program, at full size; prints a table.

    python benchmarks/lattice_acceptance.py [--seeds 100] [--loss 0.1]

Rows: each shipped car at 0 loss (every module its ``role_expected``, every fragment everywhere,
no program run twice, frames learned right, no runtime errors); car8-cyclic at the chosen loss;
``--seeds`` runs of car11 at the chosen loss with fragments injected back to back (as ``rdcd
simulate`` does) and again with each fragment diffused before the next (as the compiler's
injection plan asks); the Reverse scenario (obstacle cell ahead of a front wheel's watched
sensor) on every car at 0 loss and at the chosen loss. Figures: passes, time to settle (last
fragment accepted or role taken, simulated s), link packets sent/delivered/dropped,
retransmissions, suppressed duplicates, wall time. Exit status 1 on any failure, with details.
Harness: tests/integration/lattice_harness.py.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.integration.lattice_harness import (  # noqa: E402
    CARS,
    LatticeRun,
    compiled,
    reverse_scenario,
    start,
)


@dataclass
class Row:
    name: str
    runs: int = 0
    passed: int = 0
    settle: list[float] = field(default_factory=list)
    figures: dict[str, list[float]] = field(default_factory=dict)
    wall_s: float = 0.0
    failures: list[str] = field(default_factory=list)
    note: str = ""

    def add(self, run: LatticeRun, problems: list[str]) -> None:
        self.runs += 1
        self.passed += not problems
        figs = run.figures()
        if figs["settle_s"] is not None:
            self.settle.append(float(figs["settle_s"]))
        for key in ("sent", "delivered", "dropped", "retransmissions", "duplicates"):
            self.figures.setdefault(key, []).append(float(figs[key] or 0))
        if problems:
            self.failures.append(f"seed {run.seed}: " + "; ".join(problems[:4]))


def mean(values: list[float]) -> str:
    return f"{statistics.fmean(values):.0f}" if values else "-"


def spread(values: list[float]) -> str:
    if not values:
        return "-"
    if min(values) == max(values):
        return f"{values[0]:.2f}"
    return f"{min(values):.2f}/{statistics.median(values):.2f}/{max(values):.2f}"


def timed(row: Row, body: Callable[[], None]) -> Row:
    began = time.perf_counter()
    body()
    row.wall_s = time.perf_counter() - began
    return row


def roles_row(config: str, loss: float, seeds: range, spacing: float | None, label: str) -> Row:
    row = Row(f"{config} {label} loss {loss:g} x{len(seeds)}")

    def body() -> None:
        for seed in seeds:
            run = start(config, seed=seed, loss=loss, spacing_s=spacing)
            row.add(run, run.problems())
    return timed(row, body)


def reverse_row(config: str, loss: float, seed: int) -> Row:
    row = Row(f"{config} Reverse loss {loss:g}")

    def body() -> None:
        run = start(config, seed=seed, loss=loss)
        result = reverse_scenario(run)
        row.add(run, result.problems)
        row.note = (f"detect {result.detect_s}s, reverse {result.reverse_s}s, axles "
                    + ",".join(f"{a:+.0f}" for a in result.steered.values()))
    return timed(row, body)


def print_table(rows: list[Row]) -> None:
    head = (f"{'scenario':38} {'pass':>8} {'settle s min/med/max':>21} {'sent':>5} {'deliv':>5} "
            f"{'drop':>4} {'retx':>4} {'dups':>4} {'wall s':>7}  note")
    print(head)
    print("-" * len(head))
    for r in rows:
        f = r.figures
        print(f"{r.name:38} {f'{r.passed}/{r.runs}':>8} {spread(r.settle):>21} {mean(f.get('sent', [])):>5} "
              f"{mean(f.get('delivered', [])):>5} {mean(f.get('dropped', [])):>4} "
              f"{mean(f.get('retransmissions', [])):>4} {mean(f.get('duplicates', [])):>4} "
              f"{r.wall_s:7.2f}  {r.note}")
    print("sent ... dups: means per run, link packets including acks (Reverse rows: the whole scenario);\n"
          "settle: simulated time of the last fragment accepted or role taken before any obstacle")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=100, help="seeded car11 runs per injection mode")
    parser.add_argument("--loss", type=float, default=0.1, help="packet loss of the lossy rows")
    args = parser.parse_args(argv)
    program = compiled()
    print(f"program: {len(program.fragments)} fragments, {program.total_bytes} bytes, largest "
          f"{program.max_fragment_bytes}; injection {' -> '.join(program.injection)}\n")
    seeds = range(1, args.seeds + 1)
    rows = [roles_row(c, 0.0, range(1), 0.0, "roles") for c in CARS]
    rows.append(roles_row("car8-cyclic", args.loss, range(1, 11), 0.0, "roles"))
    rows.append(roles_row("car11", args.loss, seeds, 0.0, "back-to-back"))
    rows.append(roles_row("car11", args.loss, seeds, None, "diffused"))
    rows += [reverse_row(c, loss, 1) for loss in (0.0, args.loss) for c in CARS]
    print_table(rows)
    failures = [(r.name, f) for r in rows for f in r.failures]
    for name, failure in failures:
        print(f"FAIL {name}: {failure}")
    passed, runs = sum(r.passed for r in rows), sum(r.runs for r in rows)
    print(f"\n{'FAILED' if failures else 'PASSED'}: {passed}/{runs} runs passed "
          f"in {sum(r.wall_s for r in rows):.1f} s wall")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
