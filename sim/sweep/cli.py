"""``rdcd sweep EXPERIMENT.toml [--workers N] [--scheduler ADDRESS] [--out DIR] [--limit N]``

Runs every combination of an experiment's grid, each run exactly a ``rdcd simulate`` run, on a
local Dask cluster (one single-threaded worker process per core), in this process (``--workers
1``) or on an existing cluster (``--scheduler tcp://...``). Exit status: 0 the sweep ran (runs
that failed are results, listed in the summary), 2 a bad experiment file or option (nothing run),
130 interrupted (every finished run is kept; run the same command again to go on).
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parent / "example.toml"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("experiment", metavar="EXPERIMENT.toml", nargs="?", help="the experiment file")
    parser.add_argument("--init", metavar="FILE",
                        help="write a commented example experiment to FILE and, beside it, its program")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="worker processes of the local cluster (default: one per core); 1: in this "
                             "process, without Dask")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="use the Dask cluster at ADDRESS (tcp://host:8786)")
    parser.add_argument("--out", metavar="DIR", help="output folder (default: from the experiment, "
                                                     "else EXPERIMENT-sweep)")
    parser.add_argument("--limit", type=int, metavar="N", help="run only the first N runs of the grid")
    parser.add_argument("--retry-failed", action="store_true", help="run the runs that failed again")
    parser.add_argument("--replay", metavar="KEY", help="run one finished run again with rdcd simulate "
                                                        "(its key from runs.csv, or the start of it)")
    parser.add_argument("--summary", action="store_true",
                        help="print the summary of the runs already done and run nothing")


def _fail(message: str) -> int:
    print(f"rdcd sweep: {message}", file=sys.stderr)
    return 2


def example_program() -> Path:
    """The program the example experiment runs: the paper's obstacle avoidance in examples/."""
    return Path(__file__).resolve().parents[2] / "examples" / PROGRAM_NAME


PROGRAM_NAME = "obstacle_avoidance.rdcd"


def init(path: str) -> int:
    """Write the example experiment to ``path`` and its program beside it, so that it runs from
    any folder. Nothing is ever overwritten: an existing experiment file is refused, and an
    existing program of that name is used only when it is the same program."""
    import os

    text = EXAMPLE.read_text(encoding="utf-8")
    try:
        program = example_program().read_text(encoding="utf-8")
    except OSError:
        return _fail(f"the example program {PROGRAM_NAME} is not installed (examples/ of the rdcd "
                     "source tree: install with pip install -e .)")
    beside = Path(path).parent / PROGRAM_NAME
    writes = [(path, text)]
    try:
        if beside.read_text(encoding="utf-8") != program:
            return _fail(f"{beside} exists and is not the example program; --init writes it beside "
                         f"{path}: choose another folder")
    except FileNotFoundError:
        writes.append((str(beside), program))
    except (OSError, UnicodeDecodeError) as error:
        return _fail(f"{beside} exists and cannot be read: {getattr(error, 'strerror', None) or error}")
    done: list[str] = []
    for target, content in writes:
        try:  # O_EXCL: an existing file is never overwritten, not even one created a moment ago
            fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            problem = f"{target} exists; --init writes only a new file"
        except OSError as error:
            problem = f"cannot write {target}: {error.strerror or error}"
        else:
            with os.fdopen(fd, "w", encoding="utf-8") as file:
                file.write(content)
            done.append(target)
            continue
        for written in done:  # all or nothing: no half-written example is left behind
            os.unlink(written)
        return _fail(problem)
    program_note = (f" and its program {beside}" if len(done) == 2
                    else f" (its program: the existing {beside})")
    print(f"wrote {path}{program_note}; edit 'program' and the [grid], then: rdcd sweep {path}")
    return 0


def _usage_problem(args: argparse.Namespace) -> str | None:
    if args.init and args.experiment:
        return "give either EXPERIMENT.toml or --init FILE"
    if not args.init and not args.experiment:
        return "name an experiment file (or write one with --init FILE)"
    if args.workers is not None and args.scheduler:
        return "--workers starts a local cluster; --scheduler uses another: give one of them"
    if args.workers is not None and not 1 <= args.workers <= 1024:
        return f"--workers must be in 1..1024, not {args.workers}"
    if args.limit is not None and args.limit < 1:
        return f"--limit must be at least 1, not {args.limit}"
    if args.scheduler and "://" not in args.scheduler:
        return f"--scheduler {args.scheduler}: give an address such as tcp://host:8786"
    return None


def run(args: argparse.Namespace) -> int:
    problem = _usage_problem(args)
    if problem:
        return _fail(problem)
    if args.init:
        return init(args.init)
    from sim.sweep import ExperimentError, SweepError, load
    from sim.sweep.store import StoreError

    try:
        experiment = load(args.experiment)
        if args.replay:
            return _replay(experiment, args)
        if args.summary:
            from sim.sweep.api import open_results

            print(open_results(experiment, args.out, args.limit).table())
            return 0
        return _sweep(experiment, args)
    except (ExperimentError, SweepError, StoreError) as error:
        return _fail(str(error))


def _sweep(experiment, args: argparse.Namespace) -> int:  # noqa: ANN001 - sim.sweep.Experiment
    from sim.sweep import run as run_sweep

    needs_dask = args.workers != 1
    if needs_dask:
        try:
            import distributed  # noqa: F401
        except ImportError:
            return _fail("Dask is not installed (pip install 'dask[distributed]'); "
                         "--workers 1 runs without it")
    argv = ["rdcd", "sweep", args.experiment]
    for flag, value in (("--out", args.out), ("--limit", args.limit), ("--scheduler", args.scheduler)):
        if value is not None:
            argv += [flag, str(value)]
    command = shlex.join(argv)
    results = run_sweep(experiment, out=args.out, workers=args.workers, scheduler=args.scheduler,
                        limit=args.limit, retry_failed=args.retry_failed, command=command)
    print(results.table())
    done = f"{results.ran} runs now, {results.already} before"
    if results.failed:
        done += f", {results.failed} failed"
    print(f"{done}; results in {results.out}/ (index.html, runs.csv, summary.csv)")
    if results.interrupted:
        # counted in the folder: a Ctrl-C can fall between a run's file and its count
        kept = sum(results.plan.store.has(key) for key in results.plan.keys())
        print(f"rdcd sweep: interrupted: {kept} of {results.total} runs are done and kept in {results.out}/; "
              f"to go on, run again: {command}", file=sys.stderr)
        return 130
    return 0


def _replay(experiment, args: argparse.Namespace) -> int:  # noqa: ANN001 - sim.sweep.Experiment
    from rdcd_core.cli import main
    from sim.sweep.api import row_for

    row = row_for(experiment, args.replay, args.out)
    print(f"replaying run {row['key']}: {row['simulate']}", flush=True)
    return main(shlex.split(row["simulate"])[1:])
