"""One run of a sweep, in whatever process it lands: exactly what ``rdcd simulate`` does.

A task is plain data (JSON types): the program's text, the configuration's JSON, the option
values, the time limit and the replay command. The result is a row (sim/sweep/rows.py). Any
exception becomes a failed row with its message; the time limit is enforced with SIGALRM where
the run has the main thread (in-process and in the host process); sim/sweep/host.py adds a hard
limit around that.
"""

from __future__ import annotations

import contextlib
import datetime
import os
import signal
import socket
import threading
from collections.abc import Iterator
from functools import lru_cache
from typing import Any

from sim.sweep.rows import measures


class RunTimeout(Exception):
    pass


@lru_cache(maxsize=8)
def _compiled(text: str, vm: str | None):  # noqa: ANN202 - CompiledProgram; kept warm across runs
    from sim.sweep.options import compile_like_simulate

    _, program, _ = compile_like_simulate(text, vm)
    if program is None or program.has_errors:
        raise ValueError("the program has errors")
    return program


@contextlib.contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Raise RunTimeout in the main thread after ``seconds`` (a no-op elsewhere)."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield
        return

    def expire(signum: int, frame: object) -> None:
        raise RunTimeout

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def base_row(task: dict[str, Any]) -> dict[str, Any]:
    return {"key": task["key"], "status": "ok", "error": "", **task["options"], "simulate": task["simulate"],
            "host": f"{socket.gethostname()}:{os.getpid()}",
            "finished_at": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")}


def failed_row(task: dict[str, Any], message: str) -> dict[str, Any]:
    return {**base_row(task), "status": "failed", "error": message}


def run_task(task: dict[str, Any]) -> dict[str, Any]:
    """Run one task here and now; never raises for a problem of the run itself."""
    try:
        program = _warm(task)  # importing PyBullet and compiling are not the run's time
        with time_limit(task["time_limit_s"]):
            row = base_row(task)
            row.update(_simulate(task, program))
            return row
    except RunTimeout:
        return failed_row(task, f"exceeded the time limit of {task['time_limit_s']:g} s")
    except Exception as error:  # noqa: BLE001 - a failed run is a result, the sweep goes on
        return failed_row(task, f"{type(error).__name__}: {error}")


def _warm(task: dict[str, Any]):  # noqa: ANN202 - CompiledProgram
    from sim.quiet import import_pybullet

    import_pybullet()
    return _compiled(task["program"], task["options"].get("vm"))


def _simulate(task: dict[str, Any], program: Any) -> dict[str, Any]:
    from sim.config import structure_from_json
    from sim.run import Options, simulate
    from sim.sweep.experiment import CHANGES, parse_changes

    options = dict(task["options"])
    changes = parse_changes(options.pop(CHANGES, "") or "")
    structure = structure_from_json(task["config"], source=options.get("config", "configuration"))
    report = simulate(program, structure, Options(**options, outside_changes=changes))
    return measures(report, structure)
