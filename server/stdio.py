"""Serving LSP over stdin/stdout with our own reader (``server/framing.py``) in place of pygls's.

stdin is read by a daemon thread (a blocked read never holds the process at exit) and handed to the
event loop with back-pressure; stdout is written under a lock, one whole frame at a time, because
handlers may answer from worker threads. Anything else that prints to ``sys.stdout`` goes to stderr,
so that a stray print cannot corrupt the stream.
"""

from __future__ import annotations

import asyncio
import logging
import os
import signal
import sys
import threading
from typing import Any, BinaryIO

from server.framing import Body, FrameReader

log = logging.getLogger("rdcd.server")

CHUNK = 64 * 1024
EXIT_CLIENT_GONE = 1


class LockedWriter:
    """pygls's writer interface; a client that went away stops the server instead of raising."""

    def __init__(self, stream: BinaryIO, on_lost: Any) -> None:
        self._stream = stream
        self._lock = threading.Lock()
        self._on_lost = on_lost
        self.lost = False

    def write(self, data: bytes) -> None:
        with self._lock:
            if self.lost:
                return
            try:
                self._stream.write(data)
                self._stream.flush()
            except (OSError, ValueError):  # EPIPE, a closed stream
                self.lost = True
                self._on_lost()

    def close(self) -> None:
        with self._lock:
            self.lost = True


def serve_stdio(server: Any, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None) -> int:
    """Runs ``server`` until ``exit``, the end of stdin or SIGTERM; returns the exit status."""
    stdin = stdin or sys.stdin.buffer
    stdout = stdout or sys.stdout.buffer
    sys.stdout = sys.stderr
    try:
        return asyncio.run(_serve(server, stdin, stdout))
    except KeyboardInterrupt:
        return 130
    finally:
        pool = getattr(server, "_thread_pool", None)
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)


async def _serve(server: Any, stdin: BinaryIO, stdout: BinaryIO) -> int:
    loop = asyncio.get_running_loop()
    loop.set_exception_handler(_unretrieved)
    stop = asyncio.Event()
    status: dict[str, int] = {}

    def halt(code: int) -> None:
        status.setdefault("code", code)
        loop.call_soon_threadsafe(stop.set)

    protocol = server.protocol
    protocol.set_writer(LockedWriter(stdout, lambda: halt(EXIT_CLIENT_GONE)))
    for name in ("SIGTERM", "SIGHUP"):
        number = getattr(signal, name, None)
        if number is None:
            continue
        try:
            loop.add_signal_handler(number, halt, 128 + number)
        except (NotImplementedError, RuntimeError, ValueError):  # not the main thread, not POSIX
            pass
    chunks: asyncio.Queue[bytes] = asyncio.Queue(maxsize=16)
    threading.Thread(target=_pump, args=(stdin, loop, chunks), name="rdcd-stdin", daemon=True).start()
    reader = FrameReader()
    stopping = asyncio.ensure_future(stop.wait())
    while not stop.is_set():
        getting = asyncio.ensure_future(chunks.get())
        await asyncio.wait({getting, stopping}, return_when=asyncio.FIRST_COMPLETED)
        if not getting.done():
            getting.cancel()
            break
        chunk = getting.result()
        if not chunk:
            if reader.pending():
                log.warning("the input ended inside a message (%d bytes)", reader.pending())
            break
        for item in reader.feed(chunk):
            if isinstance(item, Body):
                protocol.receive_body(item.data)
            else:
                protocol.refuse_frame(item)
            if protocol.exit_code is not None:
                halt(protocol.exit_code)
                break
            await asyncio.sleep(0)  # let answers and checks run between the messages of one read
    stopping.cancel()
    await _end_tasks()
    if "code" in status:
        return status["code"]
    return 0 if protocol.shut_down else EXIT_CLIENT_GONE


async def _end_tasks(patience: float = 10) -> None:
    """Cancels what still runs (checks, simulations: they kill their child and remove their folder)
    and collects the outcomes, which asyncio.run would otherwise log as unhandled tracebacks."""
    tasks = [task for task in asyncio.all_tasks() if task is not asyncio.current_task()]
    for task in tasks:
        task.cancel()
    if tasks:
        done, _ = await asyncio.wait(tasks, timeout=patience)
        for task in done:
            if not task.cancelled():
                task.exception()  # retrieved: not "never retrieved"


def _unretrieved(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
    """A refusal a handler meant (a ``JsonRpcException``: a cancelled simulation, say) whose outcome
    nobody collected, because the server ended while pygls passed it on between its futures, is
    logged on one line, as when it is answered (server/protocol.py); anything else as asyncio does."""
    from pygls.exceptions import JsonRpcException

    error = context.get("exception")
    if isinstance(error, JsonRpcException):
        log.info("at the end: %s (%s)", context.get("message", "an outcome not collected"), error.message)
        return
    loop.default_exception_handler(context)


def _pump(stdin: BinaryIO, loop: asyncio.AbstractEventLoop, chunks: asyncio.Queue[bytes]) -> None:
    try:
        fd: int | None = stdin.fileno()
    except (OSError, AttributeError, ValueError):
        fd = None
    while True:
        try:
            chunk = os.read(fd, CHUNK) if fd is not None else stdin.read1(CHUNK)  # type: ignore[attr-defined]
        except OSError:
            chunk = b""
        try:
            asyncio.run_coroutine_threadsafe(chunks.put(chunk), loop).result()
        except Exception:  # the loop has closed: the server is stopping
            return
        if not chunk:
            return
