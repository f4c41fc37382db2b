"""Speed of `rdcd sweep`: throughput per worker count, parallel efficiency, scheduling overhead,
and the memory of the driver and the workers over a long sweep.

    python benchmarks/sweep_speed.py [--runs 8] [--lattice-runs 10000] [--lattice-workers 2]
                                     [--skip-lattice] [--skip-throughput]

1. ``--runs`` car7 runs of the obstacle program (wall 1 m ahead, 60 simulated seconds, seeds
   1..N), three ways: in this process (``--workers 1``, no Dask), a local Dask cluster of one
   worker and one of two. Each cluster is started and its workers warmed (one short run each)
   before the clock starts, so what is measured is the sweep, not the start of a cluster.
   Prints simulated seconds per wall second, the parallel efficiency at two workers (throughput of
   two workers / twice that of one in-process worker; target >= 85 %, aim 95 %) and the scheduling
   overhead per run: wall time x workers minus the runs' own time, per run, against a run's time
   (target < 5 %).
2. A sweep of ``--lattice-runs`` short lattice-world runs (car7, 1 s, seeds 1..N) on two workers,
   sampling the resident memory of the driver (which holds a local cluster's scheduler) and of
   the worker processes every second: it must not grow with the number of runs. Printed over the
   whole sweep and over each half (allocators settle over the first thousands of runs;
   ``--lattice-runs 30000`` shows the plateau).
Figures depend on other load on the machine: run it on a quiet one.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sim import sweep  # noqa: E402
from sim.sweep.execution import local_cluster  # noqa: E402

PROGRAM = ROOT / "examples" / "obstacle_avoidance.rdcd"


def experiment(folder: Path, name: str, world: str, duration: float, seeds: int,
               obstacle: str) -> sweep.Experiment:
    path = folder / f"{name}.toml"
    path.write_text(f"""program = "{PROGRAM}"
time_limit_s = 600
[run]
world = "{world}"
config = "car7"
obstacle = "{obstacle}"
duration = {duration}
[grid]
seed = {{ from = 1, to = {seeds} }}
[success]
checks = ["roles"]
""", encoding="utf-8")
    return sweep.load(path)


def measure(e: sweep.Experiment, out: Path, workers: int, dask: bool) -> tuple[float, float]:
    """(wall seconds running the sweep, the runs' own wall seconds added up). Writing the tables
    and plots at the end is left out: it is the same for any number of workers."""
    if not dask:
        warm = experiment(out.parent, "warm0", "physics", 1.0, 1, "wall:1.0")
        sweep.run(warm, out=out.parent / "warm0-out", workers=1, progress=False)  # imports, compiling
        results = sweep.run(e, out=out, workers=1, progress=False)
    else:
        with local_cluster(workers) as client:
            warm = experiment(out.parent, f"warm{workers}", "physics", 1.0, workers, "wall:1.0")
            sweep.run(warm, out=out.parent / f"warm{workers}-out", client=client, progress=False)
            results = sweep.run(e, out=out, client=client, progress=False)
    rows = results.rows()
    assert len(rows) == e.size and all(r["status"] == "ok" for r in rows), [r["error"] for r in rows]
    return results.run_s, sum(r["wall_time_s"] for r in rows)


def throughput(folder: Path, runs: int) -> None:
    e = experiment(folder, "car7", "physics", 60.0, runs, "wall:1.0")
    print(f"{runs} car7 runs of 60 s (obstacle program, wall 1 m ahead)")
    print(f"{'how':<26} {'wall s':>7} {'sim s / wall s':>15} {'overhead per run':>17}")
    rates = {}
    for label, workers, dask in (("in-process (--workers 1)", 1, False), ("Dask, 1 worker", 1, True),
                                 ("Dask, 2 workers", 2, True)):
        wall, own = measure(e, folder / f"out-{workers}-{dask}", workers, dask)
        rates[label] = 60.0 * runs / wall
        overhead = (wall * workers - own) / runs
        share = 100 * overhead / (own / runs)
        print(f"{label:<26} {wall:>7.1f} {rates[label]:>15.1f} {overhead:>8.3f} s {share:>5.1f} %")
    efficiency = rates["Dask, 2 workers"] / (2 * rates["in-process (--workers 1)"])
    print(f"parallel efficiency at 2 workers: {100 * efficiency:.0f} % (target >= 85 %, aim 95 %)")


def lattice_memory(folder: Path, runs: int, workers: int) -> None:
    import psutil

    e = experiment(folder, "lattice", "lattice", 1.0, runs, "none")
    samples: list[tuple[float, int, int, int]] = []  # (seconds, rows done, driver RSS, workers' RSS)
    done = threading.Event()
    me = psutil.Process()
    out = folder / "lattice-out"

    def sample() -> None:
        start = time.monotonic()
        while not done.is_set():
            # counted one entry at a time: a list of every row file would itself grow with the runs
            count = sum(1 for _ in os.scandir(out / "runs")) if (out / "runs").is_dir() else 0
            workers_rss = 0
            for child in me.children(recursive=True):
                try:
                    workers_rss += child.memory_info().rss
                except psutil.Error:  # a worker starting or stopping
                    pass
            samples.append((time.monotonic() - start, count, me.memory_info().rss, workers_rss))
            done.wait(1.0)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    start = time.perf_counter()
    try:
        results = sweep.run(e, out=out, workers=workers, progress=False)
    finally:
        done.set()
        sampler.join()
    wall = time.perf_counter() - start
    print(f"\n{runs} lattice runs (car7, 1 s) on {workers} worker(s): {wall:.0f} s "
          f"({results.run_s:.0f} s running, "
          f"{results.outputs_s:.0f} s writing tables and plots), {runs / results.run_s:.0f} runs/s, "
          f"{results.failed} failed")
    print(f"{'runs done':>10} {'driver RSS MB':>14} {'workers RSS MB':>15}")
    marks = sorted({min(range(len(samples)), key=lambda i: abs(samples[i][1] - runs * f)) for f in
                    (0.05, 0.25, 0.5, 0.75, 1.0)})
    for i in marks:
        print(f"{samples[i][1]:>10} {samples[i][2] / 1e6:>14.1f} {samples[i][3] / 1e6:>15.1f}")
    # From 10 % to 95 % of the runs: after the start (imports, first connections) and before the
    # tables and plots are written (matplotlib is imported then); in halves, as the allocators
    # settle over the first thousands of runs.
    for low, high in ((0.1, 0.95), (0.1, 0.5), (0.5, 0.95)):
        window = [s for s in samples if runs * low <= s[1] <= runs * high]
        if len(window) < 2:
            continue
        first, last = window[0], window[-1]
        for column, who in ((2, "driver"), (3, "workers'")):
            growth = (last[column] - first[column]) / max(1, last[1] - first[1])
            print(f"{who} RSS from {first[1]} to {last[1]} runs: {first[column] / 1e6:.1f} -> "
                  f"{last[column] / 1e6:.1f} MB, {growth / 1024:+.3f} KB per run")


def positive(text: str) -> int:
    """An argparse type: a whole number of at least 1 (else a usage error, not a traceback)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {value}")
    return value


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=positive, default=8)
    parser.add_argument("--lattice-runs", type=positive, default=10_000,
                        help=f"at most {sweep.MAX_RUNS:,}, what a sweep takes at once")
    parser.add_argument("--lattice-workers", type=positive, default=2,
                        help="workers of the lattice sweep (1: in this process, without Dask)")
    parser.add_argument("--skip-lattice", action="store_true")
    parser.add_argument("--skip-throughput", action="store_true")
    args = parser.parse_args()
    if args.lattice_runs > sweep.MAX_RUNS:
        parser.error(f"--lattice-runs: at most {sweep.MAX_RUNS:,}")
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, load average {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory(prefix="sweep-speed-") as tmp:
        if not args.skip_throughput:
            throughput(Path(tmp), args.runs)
        if not args.skip_lattice:
            lattice_memory(Path(tmp), args.lattice_runs, args.lattice_workers)
    return 0


if __name__ == "__main__":
    sys.exit(main())
