"""``workspace/executeCommand``: ``rdcd.simulate`` (a child process with progress and cancellation)
and ``rdcd.showBytecode`` (the compiler's listing)."""

from __future__ import annotations

import asyncio
import json
import logging
import os
import shutil
import sys
import tempfile
import time
import uuid
from pathlib import Path
from typing import Any

from lsprotocol import types
from pygls.exceptions import JsonRpcRequestCancelled

from server.guard import RequestFailed

log = logging.getLogger("rdcd.server")

SIMULATE = "rdcd.simulate"
SHOW_BYTECODE = "rdcd.showBytecode"
OPTION_FLAGS = {"config": "--config", "obstacle": "--obstacle", "duration": "--duration", "seed": "--seed",
                "world": "--world", "packetLoss": "--packet-loss", "vm": "--vm", "target": "--target"}


def simulate_arguments(program: Path, options: dict[str, Any], report: Path, plot: Path) -> list[str]:
    argv = [sys.executable, "-m", "rdcd_core", "simulate", str(program)]
    for key, flag in OPTION_FLAGS.items():
        value = options.get(key)
        if value is None:
            continue
        argv += [flag, str(value)]
    return argv + ["--report", str(report), "--plot", str(plot)]


def child_environment() -> dict[str, str]:
    """The server's environment, with this checkout first on the path (also when not installed)."""
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parent.parent)
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def _document_text(ls: Any, uri: Any) -> str:
    if not isinstance(uri, str):
        raise RequestFailed("expected the document uri as the first argument")
    document = ls.documents.get(uri)
    if document is not None:
        return document.text
    if uri.startswith("file://"):
        from pygls.uris import to_fs_path

        from rdcd_core.inputs import InputError, read_source

        path = to_fs_path(uri)
        if path and Path(path).is_file():
            try:
                return read_source(path)
            except InputError as error:
                raise RequestFailed(str(error)) from None
    raise RequestFailed(f"unknown document {uri}")


class _Progress:
    """Server-initiated work done progress, if the client supports it; silent otherwise."""

    def __init__(self, ls: Any) -> None:
        self.ls = ls
        self.token: str | None = None

    async def begin(self, title: str, on_cancel: Any) -> None:
        capabilities = self.ls.client_capabilities
        window = getattr(capabilities, "window", None)
        if not getattr(window, "work_done_progress", False):
            return
        token = f"rdcd-{uuid.uuid4()}"
        try:
            await asyncio.wait_for(self.ls.work_done_progress.create_async(token), 5)
        except Exception:
            log.info("client refused a progress token")
            return
        self.token = token
        self.ls.work_done_progress.begin(token, types.WorkDoneProgressBegin(title=title, cancellable=True))
        future = self.ls.work_done_progress.tokens.get(token)
        if future is not None:
            future.add_done_callback(lambda f: on_cancel() if f.cancelled() else None)

    def report(self, message: str) -> None:
        if self.token is not None:
            self.ls.work_done_progress.report(self.token, types.WorkDoneProgressReport(message=message))

    def end(self, message: str) -> None:
        if self.token is not None:
            self.ls.work_done_progress.end(self.token, types.WorkDoneProgressEnd(message=message))
            self.ls.work_done_progress.tokens.pop(self.token, None)
            self.token = None


def _cancel_with_request(ls: Any, task: asyncio.Task | None) -> None:
    """pygls cancels only the request's outer future on $/cancelRequest; pass that on to ``task``."""
    try:
        request = ls.protocol._request_futures.get(ls.protocol.msg_id)
    except Exception:
        request = None
    if request is not None and task is not None:
        request.add_done_callback(lambda f: task.cancel() if f.cancelled() else None)


async def run_simulation(ls: Any, uri: Any, options: Any) -> dict[str, Any]:
    text = _document_text(ls, uri)
    # the program as the editor compiles it (rdcd.target), run on the VM profile the options name
    options = {"target": ls.settings.target, **(options if isinstance(options, dict) else {})}
    folder = Path(tempfile.mkdtemp(prefix="rdcd-simulate-"))
    program, report, plot = folder / "program.rdcd", folder / "report.json", folder / "plot.png"
    program.write_text(text, encoding="utf-8")
    task = asyncio.current_task()
    _cancel_with_request(ls, task)
    progress = _Progress(ls)
    await progress.begin("RDCD simulation", lambda: task.cancel() if task is not None else None)
    process = await asyncio.create_subprocess_exec(
        *simulate_arguments(program, options, report, plot),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE, cwd=str(folder),
        env=child_environment())
    started = time.monotonic()
    try:
        communicate = asyncio.ensure_future(process.communicate())
        while not communicate.done():
            await asyncio.wait({communicate}, timeout=0.5)
            progress.report(f"simulating… {time.monotonic() - started:.0f} s")
        stdout, stderr = communicate.result()
    except asyncio.CancelledError:
        if process.returncode is None:
            process.kill()
            await process.wait()
        progress.end("cancelled")
        shutil.rmtree(folder, ignore_errors=True)
        # an Exception, not CancelledError: pygls then answers the request instead of forgetting it
        raise JsonRpcRequestCancelled("simulation cancelled") from None
    if process.returncode != 0 or not report.is_file():
        progress.end("failed")
        shutil.rmtree(folder, ignore_errors=True)
        lines = (stderr or stdout).decode("utf-8", "replace").strip().splitlines()
        reason = lines[-1] if lines else f"exit status {process.returncode}"
        raise RequestFailed(f"simulation failed: {reason}")
    progress.end("done")
    return {"report": json.loads(report.read_text(encoding="utf-8")),
            "plotPath": str(plot) if plot.is_file() else None}


def bytecode_listing(ls: Any, uri: Any) -> str:
    """The listing of ``rdcd compile --format listing`` for the document as it is in the editor."""
    from rdcd_core.compiler import add_source_lines
    from rdcd_core.compiler.render import render_listing
    from rdcd_core.diagnostics import Severity
    from rdcd_core.ide.analysis import analyze

    text = _document_text(ls, uri)
    document = ls.documents.get(uri)  # an open document's text is ``text``: reuse its analysis
    analysis = document.current() if document is not None else analyze(text, target=ls.settings.target)
    errors = [d for d in analysis.diagnostics if d.severity is Severity.ERROR]
    program = analysis.compiled() if analysis.model is not None and not errors else None
    if program is None:
        reason = errors[0].message if errors else "the program could not be checked"
        raise RequestFailed(f"cannot compile: {reason}")
    add_source_lines(program.fragments, analysis.line_index)
    return render_listing(program)


def register(server: Any) -> None:
    @server.command(SIMULATE)
    async def simulate(ls, *args):  # type: ignore[no-untyped-def]
        uri = args[0] if args else None
        options = args[1] if len(args) > 1 else {}
        return await run_simulation(ls, uri, options)

    @server.command(SHOW_BYTECODE)
    def show_bytecode(ls, *args):  # type: ignore[no-untyped-def]
        return bytecode_listing(ls, args[0] if args else None)
