"""`rdcd sweep` on real Dask clusters: a local cluster of two workers gives the rows of
`--workers 1`; a killed worker loses nothing; crashing and hanging runs are recorded as failed;
a cluster of separate `dask scheduler` and `dask worker` processes is used through --scheduler."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from rdcd_core.cli import main  # noqa: E402
from sim import sweep  # noqa: E402
from tests.sweep.helpers import LATTICE, comparable, env, experiment, fault_folder, rdcd, stored_rows  # noqa: E402


def test_two_workers_give_the_rows_of_one(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = experiment(tmp_path)
    monkeypatch.chdir(tmp_path)  # where the other runs: replay commands name the program from there
    assert main(["sweep", str(path), "--workers", "1", "--out", str(tmp_path / "one")]) == 0
    result = rdcd("sweep", str(path), "--workers", "2", "--out", str(tmp_path / "two"), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    one, two = stored_rows(tmp_path / "one"), stored_rows(tmp_path / "two")
    assert len(one) == 12
    assert {k: comparable(r) for k, r in two.items()} == {k: comparable(r) for k, r in one.items()}
    assert len({r["host"] for r in two.values()}) == 2  # both workers ran some
    assert (tmp_path / "two" / "runs.csv").read_text(encoding="utf-8").count("\n") == 13


def test_a_killed_worker_loses_no_finished_row_and_the_sweep_completes(tmp_path: Path) -> None:
    from distributed import Client, LocalCluster

    path = experiment(tmp_path, LATTICE.replace("duration = 8", "duration = 30").replace("to = 3", "to = 4"))
    out = tmp_path / "out"
    seen: dict[str, tuple[bytes, int]] = {}
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        victim = next(iter(client.run(os.getpid).values()))

        def kill_after_three_rows() -> None:
            deadline = time.monotonic() + 240
            while len(list((out / "runs").glob("*.json"))) < 3 and time.monotonic() < deadline:
                time.sleep(0.02)
            files = (out / "runs").glob("*.json")
            seen.update({p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in files})
            os.kill(victim, signal.SIGKILL)

        killer = threading.Thread(target=kill_after_three_rows)
        killer.start()
        results = sweep.run(sweep.load(path), out=out, client=client, progress=False)
        killer.join()
        assert _replaced(client, victim)  # it really died (and the nanny started another)
    assert len(seen) >= 3
    rows = stored_rows(out)
    assert len(rows) == 16 and results.ran == 16
    assert all(r["status"] == "ok" for r in rows.values()), [r["error"] for r in rows.values()]
    for name, content in seen.items():
        assert ((out / "runs" / name).read_bytes(), (out / "runs" / name).stat().st_mtime_ns) == content


def _replaced(client: object, victim: int, timeout: float = 60.0) -> bool:
    """Whether ``victim`` is gone from the cluster's workers: the scheduler notices a killed worker
    only after a moment, and asking the dead one meanwhile fails, so ask again until it has."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            if victim not in client.run(os.getpid).values():  # type: ignore[attr-defined]
                return True
        except Exception:  # noqa: BLE001 - the dead worker is still listed: ask again
            pass
        time.sleep(0.2)
    return False


def test_crashing_and_hanging_runs_are_recorded_as_failed(tmp_path: Path) -> None:
    text = "time_limit_s = 3\n" + LATTICE.replace('config = ["car7", "car11"]', 'config = ["car7"]').replace(
        "[0.0, 0.3]", "[0.0]").replace("from = 1, to = 3", "from = 2, to = 7")
    path = experiment(tmp_path, text)
    faults = fault_folder(tmp_path)
    result = rdcd("sweep", str(path), "--workers", "2", "--out", str(tmp_path / "out"), cwd=tmp_path,
                  PYTHONPATH=str(faults), RDCD_TEST_FAULTS="1")
    assert result.returncode == 0, result.stderr
    rows = {r["seed"]: r for r in stored_rows(tmp_path / "out").values()}
    assert rows[2]["status"] == rows[7]["status"] == "ok"
    assert rows[3]["status"] == "failed" and "crashed its process (killed by SIGSEGV)" in rows[3]["error"]
    assert rows[4]["status"] == "failed" and "exceeded the time limit of 3 s" in rows[4]["error"]
    assert rows[5]["status"] == "failed" and rows[5]["error"] == "RuntimeError: injected failure"
    assert rows[6]["status"] == "failed" and "did not answer and was killed" in rows[6]["error"]
    assert "4 failed" in result.stdout
    # Failed runs are results: running again does nothing, unless asked to retry them.
    again = rdcd("sweep", str(path), "--workers", "2", "--out", str(tmp_path / "out"), "--retry-failed",
                 cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert "4 runs now, 2 before" in again.stdout
    assert all(r["status"] == "ok" for r in stored_rows(tmp_path / "out").values())


def _start(command: list[str], log: Path) -> subprocess.Popen[bytes]:
    with open(log, "wb") as file:
        return subprocess.Popen(command, env=env(), stdout=file, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, start_new_session=True)


def _stop(processes: list[subprocess.Popen[bytes]]) -> None:
    for process in reversed(processes):  # workers first, then the scheduler
        try:
            os.killpg(process.pid, signal.SIGTERM)
        except ProcessLookupError:
            continue
    for process in processes:
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            pass
        try:
            os.killpg(process.pid, signal.SIGKILL)  # anything left in its group, hosts included
        except ProcessLookupError:
            pass
        process.wait()


def test_a_cluster_of_separate_scheduler_and_worker_processes(tmp_path: Path) -> None:
    dask = str(Path(sys.executable).parent / "dask")
    info = tmp_path / "scheduler.json"
    processes = []
    try:
        processes.append(_start([dask, "scheduler", "--port", "0", "--no-dashboard", "--scheduler-file",
                                 str(info)], tmp_path / "scheduler.log"))
        deadline = time.monotonic() + 60
        while not info.is_file() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(info.read_text(encoding="utf-8"))["address"]
        for i in range(2):
            processes.append(_start([dask, "worker", address, "--nthreads", "1", "--nworkers", "1",
                                     "--no-dashboard"], tmp_path / f"worker{i}.log"))
        path = experiment(tmp_path)
        result = rdcd("sweep", str(path), "--scheduler", address, "--out", str(tmp_path / "out"),
                      cwd=tmp_path)
        assert result.returncode == 0, result.stderr
        rows = stored_rows(tmp_path / "out")
        assert len(rows) == 12 and all(r["status"] == "ok" for r in rows.values())
        assert "12 runs now" in result.stdout
    finally:
        _stop(processes)
    assert all(p.returncode is not None for p in processes)


@pytest.mark.parametrize("workers", ["1", "2"])
def test_interrupted_sweep_keeps_finished_runs_and_resumes_with_the_missing_ones(tmp_path: Path,
                                                                                workers: str) -> None:
    """Ctrl-C as a terminal sends it: SIGINT to the whole process group (workers and hosts too)."""
    path = experiment(tmp_path, LATTICE.replace("duration = 8", "duration = 20"))
    out = tmp_path / "out"
    command = [sys.executable, "-m", "rdcd_core", "sweep", str(path), "--workers", workers, "--out", str(out)]
    process = subprocess.Popen(command, env=env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while len(list((out / "runs").glob("*.json"))) < 3 and time.monotonic() < deadline:
            time.sleep(0.05)
        os.killpg(process.pid, signal.SIGINT)
        _, err = process.communicate(timeout=120)
    finally:
        try:
            os.killpg(process.pid, signal.SIGKILL)  # whatever is left of the group
        except ProcessLookupError:
            pass
    assert process.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    said = [line for line in err.splitlines() if not line.startswith("[")]  # not the progress bar
    assert len(said) == 1, err
    assert said[0].startswith("rdcd sweep: interrupted: ") and " of 12 runs are done and kept in " in said[0]
    assert said[0].endswith(f"to go on, run again: rdcd sweep {path} --out {out}")
    kept = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in (out / "runs").glob("*.json")}
    assert 3 <= len(kept) < 12
    assert f"interrupted: {len(kept)} of 12 runs are done" in err
    with open(out / "runs.csv", encoding="utf-8") as file:  # the table holds what had finished
        assert len(list(csv.DictReader(file))) == len(kept)
    again = subprocess.run(command, env=env(), capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert f"{12 - len(kept)} runs now, {len(kept)} before" in again.stdout
    for name, content in kept.items():
        assert ((out / "runs" / name).read_bytes(), (out / "runs" / name).stat().st_mtime_ns) == content
    assert len(stored_rows(out)) == 12
    assert all(r["status"] == "ok" for r in stored_rows(out).values())


def _history(dask_scheduler) -> tuple[int, int]:  # type: ignore[no-untyped-def]
    """(the longest span metadata list, key_split's cache entries) on the scheduler."""
    from dask.utils import key_split

    spans = dask_scheduler.extensions["spans"].spans.values()
    longest = max((len((span.metadata or {}).get("collections", [])) for span in spans), default=0)
    return longest, key_split.cache_info().currsize


def test_the_scheduler_forgets_what_it_keeps_per_submission() -> None:
    """Dask keeps an entry per ``client.submit`` in its span metadata, for ever, and every key in
    a cache: run_dask trims both, or a long sweep's scheduler (the driver, on a local cluster)
    grows with the number of runs."""
    import uuid

    from distributed import Client, Event, LocalCluster

    from sim.sweep.execution import TASK_PREFIX, forget_scheduler_history, forget_worker_history

    def wait_for(event: Event) -> bool:
        return event.wait(60)

    # processes=False: the worker's cache is the scheduler's, so clearing both is checked too
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        shared = client.scatter(["the program"], broadcast=True, hash=False)[0]
        # one run stays in flight, as in a sweep's window: the group of runs never empties
        release = Event(f"release-{uuid.uuid4().hex}")
        blocker = client.submit(wait_for, release, key=f"{TASK_PREFIX}-blocker-{uuid.uuid4().hex[:8]}")
        for index in range(300):
            future = client.submit(len, shared, key=f"{TASK_PREFIX}-{index:x}-{uuid.uuid4().hex[:8]}")
            assert future.result() == len("the program")
            future.release()
        longest, cached = client.run_on_scheduler(_history)
        assert longest >= 300 and cached >= 300  # what Dask does: if this fails, the trim may be moot
        client.run_on_scheduler(forget_scheduler_history)
        client.run(forget_worker_history)
        longest, cached = client.run_on_scheduler(_history)
        assert longest == 1 and cached < 10  # the cluster's own traffic may cache a key or two meanwhile
        release.set()
        assert blocker.result() is True
