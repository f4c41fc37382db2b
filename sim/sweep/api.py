"""The sweep as a Python API (for notebooks and scripts); ``rdcd sweep`` is a thin shell on it.

    from sim import sweep
    experiment = sweep.load("experiments/robustness.toml")
    results = sweep.run(experiment, workers=2)       # or client=dask.distributed.Client(...)
    results.rows(), results.summary(), results.dataframe()
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sim.sweep.execution import cores, local_cluster, run_dask, run_serial
from sim.sweep.experiment import Experiment
from sim.sweep.plan import Plan, shown
from sim.sweep.progress import Progress
from sim.sweep.store import Store
from sim.sweep.tables import rows, summary, summary_text, write_parquet, write_runs_csv, write_summary_csv

MAX_RUNS = 1_000_000  # a larger grid needs --limit: it is a typo far more often than a plan
CSV_EVERY_S = 60.0  # runs.csv is regenerated this often during a sweep (rows are saved at once anyway)


class SweepError(ValueError):
    """A sweep that cannot start; one line."""


@dataclass
class Results:
    plan: Plan
    total: int = 0
    already: int = 0
    ran: int = 0
    failed: int = 0
    lost: int = 0
    interrupted: bool = False
    outputs: list[Path] = field(default_factory=list)
    run_s: float = 0.0  # wall seconds running the missing runs
    outputs_s: float = 0.0  # wall seconds writing tables, plots and index.html

    @property
    def out(self) -> Path:
        return self.plan.store.root

    def rows(self) -> list[dict[str, Any]]:
        """Every finished run of the experiment, in grid order, with its verdict ``success``."""
        return list(rows(self.plan))

    def summary(self) -> list[dict[str, Any]]:
        """One row per grid cell: runs, failed, successes, success_rate, ci95_low, ci95_high."""
        return summary(self.plan)

    def table(self) -> str:
        return summary_text(self.plan, self.summary())

    def dataframe(self) -> Any:
        """The rows as a pandas DataFrame (pandas is not a dependency of rdcd: install it)."""
        import pandas as pd

        return pd.DataFrame(self.rows())


def default_out(experiment: Experiment) -> Path:
    return experiment.out if experiment.out is not None else Path(f"{experiment.path.stem}-sweep")


def open_results(experiment: Experiment, out: str | Path | None = None, limit: int | None = None) -> Results:
    """The results already in the output folder, without running anything."""
    return Results(_plan(experiment, out, limit))


def _plan(experiment: Experiment, out: str | Path | None, limit: int | None) -> Plan:
    from sim.sweep.store import StoreError

    if limit is not None and limit < 1:
        raise SweepError(f"--limit must be at least 1, not {limit}")
    if limit is None and experiment.size > MAX_RUNS:
        raise SweepError(f"{experiment.path}: the grid has {experiment.size:,} runs, more than the "
                         f"{MAX_RUNS:,} a sweep takes at once: narrow the grid or pass --limit N")
    root = Path(out) if out is not None else default_out(experiment)
    inputs = [experiment.path, experiment.program_path]
    inputs += [Path(c.replay) for c in experiment.configs.values() if c.replay and Path(c.replay).is_file()]
    about = {"experiment": str(experiment.path.resolve()), "program": str(experiment.program_path.resolve()),
             "grid": experiment.grid.names, "runs": experiment.size}
    try:
        return Plan(experiment, Store.open(root, inputs, about), limit)
    except OSError as error:
        raise StoreError(f"{root}: cannot write: {error.strerror or error}") from None


def run(experiment: Experiment, *, out: str | Path | None = None, workers: int | None = None,
        scheduler: str | None = None, client: Any = None, limit: int | None = None,
        retry_failed: bool = False, progress: bool = True, command: str | None = None,
        warn: Callable[[str], None] | None = None) -> Results:
    """Run the experiment's missing runs and write its tables, plots and index.html.

    Where: ``client`` (a dask.distributed Client you made), ``scheduler`` (an address such as
    tcp://host:8786), ``workers=1`` (this process, no Dask) or else a local cluster of ``workers``
    single-threaded processes (default: one per core). Ctrl-C stops it; every finished run is kept.
    """
    plan = _plan(experiment, out, limit)
    results = Results(plan, total=plan.total)
    warn = warn or (lambda message: print(f"rdcd sweep: {message}", file=sys.stderr))
    pending = plan.count_pending(retry_failed)
    results.already = plan.total - pending
    bar = Progress(plan.total, results.already) if progress else None
    last_csv = [time.monotonic()]

    def on_row(row: dict[str, Any]) -> None:
        plan.store.write(row)
        results.ran += 1
        results.failed += row["status"] != "ok"
        if bar:
            bar.update(row["status"] != "ok")
        if time.monotonic() - last_csv[0] > CSV_EVERY_S:
            write_runs_csv(plan)
            last_csv[0] = time.monotonic()

    start = time.perf_counter()
    try:
        if pending:
            if bar:
                bar.show()
            results.lost = _execute(plan, on_row, workers, scheduler, client, retry_failed, warn)
    except KeyboardInterrupt:
        results.interrupted = True
    finally:
        results.run_s = time.perf_counter() - start
        if bar and pending:
            bar.show(final=True)
        results.outputs = write_outputs(plan, command or f"rdcd sweep {shown(experiment.path)}")
        results.outputs_s = time.perf_counter() - start - results.run_s
    return results


def _execute(plan: Plan, on_row: Callable[[dict[str, Any]], None], workers: int | None, scheduler: str | None,
             client: Any, retry_failed: bool, warn: Callable[[str], None]) -> int:
    tasks = plan.pending(retry_failed)
    if client is not None:
        return run_dask(client, tasks, on_row, warn)
    if scheduler is None and workers == 1:
        run_serial(tasks, on_row)
        return 0
    from distributed import Client

    if scheduler is not None:
        try:
            remote = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as error:
            raise SweepError(f"cannot reach the Dask scheduler at {scheduler}: {error}") from None
        with remote:
            return run_dask(remote, tasks, on_row, warn)
    with local_cluster(workers or cores()) as local:
        return run_dask(local, tasks, on_row, warn)


def write_outputs(plan: Plan, command: str) -> list[Path]:
    """runs.csv, runs.parquet (when pyarrow is there and not refused), summary.csv, plots, index.html."""
    from sim.sweep.plots import write_index, write_plots

    written = [write_runs_csv(plan)]
    if plan.experiment.parquet is not False:
        parquet = write_parquet(plan)
        if parquet:
            written.append(parquet)
    cells = summary(plan)
    written.append(write_summary_csv(plan, cells))
    images = write_plots(plan)
    written += images
    written.append(write_index(plan, cells, images, command))
    return written


def row_for(experiment: Experiment, key: str, out: str | Path | None = None) -> dict[str, Any]:
    """The stored row of a run, by its key or the start of it (for replaying)."""
    root = Path(out) if out is not None else default_out(experiment)
    found = Store(root).find(key)
    if len(found) != 1:
        what = "no finished run" if not found else f"{len(found)} runs"
        raise SweepError(f"{root}: {what} with key {key!r}")
    return json.loads(Store(root).path(found[0]).read_text(encoding="utf-8"))
