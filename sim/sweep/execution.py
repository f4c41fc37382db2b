"""Running tasks: in this process one after another, or on Dask workers with a bounded window.

The driver alone writes rows (``on_row``), so a cluster needs no shared file system, and only a
window of tasks is ever in flight, so memory does not grow with the size of the grid.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import uuid
from collections.abc import Callable, Iterator
from typing import Any

from sim.sweep.execute import failed_row, run_task

OnRow = Callable[[dict[str, Any]], None]


def cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def run_serial(tasks: Iterator[dict[str, Any]], on_row: OnRow) -> None:
    """``--workers 1``: in this process, without Dask (for debugging and small CI runs)."""
    for task in tasks:
        on_row(run_task(task))


def local_cluster(workers: int) -> Any:
    """One single-threaded worker process per core: PyBullet holds the GIL, and the simulator
    redirects file descriptors process-wide, so threads would not help."""
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                        silence_logs=logging.ERROR)


def _shared(client: Any, shared: dict[str, Any], value: Any) -> Any:
    """A future of ``value`` on the cluster, scattered the first time it is seen: tasks then carry
    a few hundred bytes instead of the program's text and the configuration each."""
    digest = hashlib.sha256(json.dumps(value, sort_keys=True).encode("utf-8")).hexdigest()
    if digest not in shared:
        # In a list: a dict given alone would be scattered key by key under its own keys ("modules"),
        # and the next configuration's "modules" would find the first one's already there.
        shared[digest] = client.scatter([value], broadcast=True, hash=False)[0]
    return shared[digest]


def run_dask(client: Any, tasks: Iterator[dict[str, Any]], on_row: OnRow,
             warn: Callable[[str], None]) -> int:
    """Run the tasks on the client's cluster; returns how many were lost to the cluster itself
    (not recorded, so they run again next time)."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    from sim.sweep.host import run_hosted

    window = 2 * max(1, sum(client.nthreads().values()))
    shared: dict[str, Any] = {}  # the program and configurations, sent to the workers once
    inflight: dict[Any, dict[str, Any]] = {}
    keys: set[str] = set()
    completed = as_completed()
    lost = 0

    def submit_next() -> None:
        for task in tasks:
            if task["key"] in keys:  # the grid names the same run twice: it runs once
                continue
            slim = {k: v for k, v in task.items() if k not in ("program", "config")}
            future = client.submit(run_hosted, slim, _shared(client, shared, task["program"]),
                                   _shared(client, shared, task["config"]),
                                   key=f"rdcd-run-{task['key']}-{uuid.uuid4().hex[:8]}")
            inflight[future] = task
            keys.add(task["key"])
            completed.add(future)
            return

    try:
        for _ in range(window):
            submit_next()
        for future in completed:
            task = inflight.pop(future)
            keys.discard(task["key"])
            try:
                on_row(future.result())
            except KilledWorker as error:
                on_row(failed_row(task, f"the worker running it died again and again ({error}); "
                                        "rdcd sweep --retry-failed runs it once more"))
            except Exception as error:  # noqa: BLE001 - the cluster, not the run: not recorded
                lost += 1
                warn(f"run {task['key']} not recorded ({type(error).__name__}: {error}); it runs next time")
            finally:
                future.release()
            submit_next()
    finally:
        if inflight:
            client.cancel(list(inflight))
    return lost
