"""A warm child process that runs one task at a time, so a run that crashes the interpreter
(a segfault in PyBullet) or hangs in C code costs only that run, never the worker around it.

The parent (a Dask worker) keeps one host alive across tasks, so PyBullet stays imported and the
program compiled. Messages are length-prefixed JSON on the child's stdin and stdout; the child
moves its own stdout to stderr first, so whatever a library prints cannot corrupt them.
"""

from __future__ import annotations

import json
import os
import select
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import IO, Any

GRACE_S = 5.0  # beyond the run's own time limit (which the child enforces), the parent kills it
START_S = 300.0  # a new host imports PyBullet and the simulator: slow on a loaded machine
_HEADER = struct.Struct(">Q")
ROOT = str(Path(__file__).resolve().parent.parent.parent)


def _send(stream: IO[bytes], message: Any) -> None:
    data = json.dumps(message).encode("utf-8")
    stream.write(_HEADER.pack(len(data)) + data)
    stream.flush()


def _receive(stream: IO[bytes]) -> Any | None:
    header = stream.read(_HEADER.size)
    if len(header) < _HEADER.size:
        return None
    data = stream.read(_HEADER.unpack(header)[0])
    return json.loads(data)


class Host:
    """The parent's handle on one child; ``run`` restarts the child when it has died."""

    def __init__(self) -> None:
        self.process: subprocess.Popen[bytes] | None = None
        self.log = tempfile.TemporaryFile("a+b")  # noqa: SIM115 - the child's stderr, for crash messages

    def _start(self) -> bool:
        """Start a child and wait until it has imported the simulator (it says "ready")."""
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(p for p in (ROOT, env.get("PYTHONPATH")) if p)
        self.process = subprocess.Popen([sys.executable, "-m", "sim.sweep.host"], stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, stderr=self.log, env=env, close_fds=True)
        assert self.process.stdout
        ready, _, _ = select.select([self.process.stdout], [], [], START_S)
        if ready and _receive(self.process.stdout) == "ready":
            return True
        self.process.kill()  # _crash_message reads how it ended
        self.process.wait()
        return False

    def run(self, task: dict[str, Any]) -> dict[str, Any]:
        from sim.sweep.execute import failed_row

        self.log.seek(0)
        self.log.truncate()
        if (self.process is None or self.process.poll() is not None) and not self._start():
            return failed_row(task, self._crash_message("the process that runs simulations did not start"))
        process = self.process
        assert process is not None
        assert process.stdin and process.stdout
        try:
            _send(process.stdin, task)
        except OSError:
            return failed_row(task, self._crash_message())
        limit = task["time_limit_s"] + GRACE_S
        ready, _, _ = select.select([process.stdout], [], [], limit)
        if not ready:
            self.stop()
            return failed_row(task, f"exceeded the time limit of {task['time_limit_s']:g} s "
                                    "(the run did not answer and was killed)")
        row = _receive(process.stdout)
        return row if row is not None else failed_row(task, self._crash_message())

    def _crash_message(self, what: str = "the run crashed its process") -> str:
        process = self.process
        code = process.wait() if process else None
        self.process = None
        self.log.seek(0)
        text = self.log.read().decode("utf-8", "replace")
        lines = [line.strip() for line in text.splitlines() if line.strip()]
        how = (f"killed by {signal.Signals(-code).name}" if code is not None and code < 0 and
               -code in signal.valid_signals() else f"exit status {code}")
        last = f": {lines[-1][:300]}" if lines else ""
        return f"{what} ({how}){last}"

    def stop(self) -> None:
        if self.process is not None:
            self.process.kill()
            self.process.wait()
            self.process = None


_HOST: Host | None = None
_LOCK = threading.Lock()


def run_hosted(task: dict[str, Any], program: str | None = None,
               config: dict[str, Any] | None = None) -> dict[str, Any]:
    """The function a Dask worker runs for each task: through this process's warm host. The
    program's text and the configuration may come apart from the task (sent to workers once)."""
    global _HOST
    if program is not None:
        task = {**task, "program": program, "config": config}
    with _LOCK:  # one simulation at a time per worker process, whatever its thread count
        if _HOST is None:
            _HOST = Host()
        return _HOST.run(task)


def _orphan_watch(parent: int) -> None:
    """Leave when the parent is gone (killed worker): stdin EOF only shows between runs."""
    while True:
        time.sleep(1.0)
        if os.getppid() != parent:
            os._exit(1)


def main() -> None:
    # Ctrl-C in a terminal reaches the whole process group: the sweep stops, but a run cut short
    # here must not come back as a crashed run. The parent decides when this process ends.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    requests = os.fdopen(os.dup(0), "rb")
    replies = os.fdopen(os.dup(1), "wb")
    devnull = os.open(os.devnull, os.O_RDONLY)
    os.dup2(devnull, 0)
    os.dup2(2, 1)  # print() and C output of libraries go to the log, not into the replies
    sys.stdout = sys.stderr
    threading.Thread(target=_orphan_watch, args=(os.getppid(),), daemon=True).start()
    from sim.quiet import import_pybullet
    from sim.sweep.execute import run_task

    import_pybullet()
    _send(replies, "ready")
    while (task := _receive(requests)) is not None:
        _send(replies, run_task(task))


if __name__ == "__main__":
    main()
