"""Running tasks: in this process one after another, or on Dask workers with a bounded window.

The driver alone writes rows (``on_row``), so a cluster needs no shared file system, and only a
window of tasks is ever in flight, so memory does not grow with the size of the grid.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import signal
import threading
import uuid
from collections.abc import Callable, Iterator
from contextlib import contextmanager
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


#: Dask's bounded logs of recent messages and transitions (1,000 entries each per connection) and
#: its system monitor (7,200 samples, an hour) fill up over the first few thousand runs; with the
#: scheduler in the driver they are the driver's memory, and no dashboard reads them here.
DRIVER_HISTORY = {"distributed.admin.low-level-log-length": 64,
                  "distributed.admin.system-monitor.log-length": 64}

#: Runs between two ``forget_scheduler_history`` calls.
FORGET_EVERY = 256

TASK_PREFIX = "rdcd-run"


@contextmanager
def local_cluster(workers: int) -> Iterator[Any]:
    """A client of a new local cluster: one single-threaded worker process per core (PyBullet holds
    the GIL, and the simulator redirects file descriptors process-wide, so threads would not help)."""
    import dask
    from distributed import Client, LocalCluster

    # No dashboard: its task stream keeps a record of every task (up to 100,000), so the driver,
    # which holds a local cluster's scheduler, would grow with the number of runs. Dask's own logs
    # only at CRITICAL: a worker whose heartbeat meets the scheduler closing after a Ctrl-C logs an
    # ERROR with a traceback (a failed run is the sweep's to report, and it does).
    # Ctrl-C is the driver's to handle (it stops, keeps every finished run and closes the cluster):
    # a worker that took it too would print Dask's KeyboardInterrupt traceback as it dies. Worker
    # processes inherit "ignore SIGINT" from the driver, which ignores it while the cluster starts
    # them (a blocked mask would not do: the spawned interpreters do not keep it), and the preload
    # keeps it so in a worker the nanny starts again later. A Ctrl-C while the cluster starts (a
    # second or two; longer on a loaded machine) is lost: press it again.
    with dask.config.set(DRIVER_HISTORY):
        with _sigint_ignored():
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=logging.CRITICAL,
                                   preload=["sim.sweep.worker_signals"])
        with cluster, Client(cluster) as client:
            yield client


@contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored by this process, and inherited so by the processes it starts, for the block."""
    if threading.current_thread() is not threading.main_thread():
        yield  # signals are the main thread's to change
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def forget_scheduler_history(dask_scheduler: Any) -> None:
    """Run on the scheduler (``client.run_on_scheduler``): drop what it keeps for every submission
    of ours although nothing reads it back, so a long sweep does not grow its memory.

    - Every ``client.submit`` appends ``{"type": "Future"}`` to the metadata of the span holding the
      task's group and of the spans holding the groups it depends on, and spans live as long as the
      scheduler (distributed 2026.8): those lists grow by an entry per run. Duplicates say nothing:
      keep one of each.
    - The key cache, as on the workers (``forget_worker_history``).
    """
    spans = getattr(dask_scheduler.extensions.get("spans"), "spans", {})
    ours = [group for name, group in list(dask_scheduler.task_groups.items())
            if isinstance(name, str) and name.startswith(TASK_PREFIX)]
    # the scattered program and configurations may sit in another span, which gets the entry too
    groups = ours + [dependency for group in ours for dependency in group.dependencies]
    for span_id in {group.span_id for group in groups if group.span_id}:
        metadata = getattr(spans.get(span_id), "_metadata", None)
        if isinstance(metadata, dict) and isinstance(metadata.get("collections"), list):
            distinct: list[Any] = []
            for collection in metadata["collections"]:
                if collection not in distinct:
                    distinct.append(collection)
            metadata["collections"][:] = distinct
    forget_worker_history()


def forget_worker_history() -> None:
    """Run on each worker (``client.run``), and on the scheduler by ``forget_scheduler_history``:
    ``dask.utils.key_split`` caches up to 100,000 keys, each of ours seen once; clear it (a cache)."""
    from dask.utils import key_split

    key_split.cache_clear()


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
    finished = 0
    # housekeeping on the scheduler and the workers, until one of them cannot run it (rdcd not
    # importable on an external scheduler): it only saves memory, so the sweep goes on without it
    forgetting = {"scheduler": True, "workers": True}

    def forget_history() -> None:
        for where, run in (("scheduler", lambda: client.run_on_scheduler(forget_scheduler_history)),
                           ("workers", lambda: client.run(forget_worker_history))):
            if not forgetting[where]:
                continue
            try:
                run()
            except Exception as error:  # noqa: BLE001 - see above
                forgetting[where] = False
                logging.getLogger(__name__).debug("%s history not trimmed: %s", where, error)

    def submit_next() -> None:
        for task in tasks:
            if task["key"] in keys:  # the grid names the same run twice: it runs once
                continue
            slim = {k: v for k, v in task.items() if k not in ("program", "config")}
            future = client.submit(run_hosted, slim, _shared(client, shared, task["program"]),
                                   _shared(client, shared, task["config"]),
                                   key=f"{TASK_PREFIX}-{task['key']}-{uuid.uuid4().hex[:8]}")
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
            finished += 1
            if finished % FORGET_EVERY == 0:
                forget_history()
            submit_next()
    finally:
        if inflight:
            client.cancel(list(inflight))
    return lost
