"""``workspace/executeCommand``: ``rdcd.simulate`` (a child process with progress and cancellation)
and ``rdcd.showBytecode`` (the compiler's listing)."""

from __future__ import annotations

import asyncio
import json
import logging
import math
import os
import re
import shutil
import sys
import time
import uuid
from pathlib import Path
from typing import Any

from lsprotocol import types
from pygls.exceptions import JsonRpcRequestCancelled

from server import scratch
from server.guard import RequestFailed

log = logging.getLogger("rdcd.server")

SIMULATE = "rdcd.simulate"
SHOW_BYTECODE = "rdcd.showBytecode"
OPTION_FLAGS = {"config": "--config", "obstacle": "--obstacle", "duration": "--duration", "seed": "--seed",
                "world": "--world", "packetLoss": "--packet-loss",
                "vm": "--vm", "target": "--target"}
MAX_OPTION_LENGTH = 4096


def checked_options(options: Any) -> dict[str, str]:
    """The options as command-line values; anything that cannot be one is refused in one line (a NUL
    would otherwise end in a traceback from ``exec``, a value ``--gui`` would be taken as a flag)."""
    if options is None:
        return {}
    if not isinstance(options, dict):
        raise RequestFailed("the options of rdcd.simulate are an object such as {\"config\": \"car7\"}")
    values = {}
    for key, value in options.items():
        if key not in OPTION_FLAGS:
            raise RequestFailed(f"unknown simulate option {key!r} (known: {', '.join(OPTION_FLAGS)})")
        if value is None:
            continue
        if isinstance(value, float) and not math.isfinite(value):
            raise RequestFailed(f"simulate option {key}: {value} is not a finite number")
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            kind = type(value).__name__
            raise RequestFailed(f"simulate option {key} must be a string or a number, not {kind}")
        text = value if isinstance(value, str) else repr(value)
        bad = next((c for c in text if not c.isprintable() or 0xD800 <= ord(c) <= 0xDFFF), None)
        if bad is not None:
            raise RequestFailed(f"simulate option {key} contains the character U+{ord(bad):04X}, which no "
                                "option can contain")
        if len(text) > MAX_OPTION_LENGTH:
            raise RequestFailed(f"simulate option {key} is longer than {MAX_OPTION_LENGTH} characters")
        values[key] = text
    return values


def simulate_arguments(program: Path, options: dict[str, str], report: Path, plot: Path,
                       replay: Path) -> list[str]:
    argv = [sys.executable, "-m", "rdcd_core", "simulate", str(program)]
    for key, flag in OPTION_FLAGS.items():
        if key in options:
            argv.append(f"{flag}={options[key]}")  # one word: a value starting with '-' stays a value
    return argv + [f"--report={report}", f"--plot={plot}", f"--replay={replay}"]


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
    values = checked_options(options)
    # the program as the editor compiles it (rdcd.target), run on the VM profile the options name
    values.setdefault("target", ls.settings.target)
    shown = display_path(uri)
    first = await _first_error_in_editor(ls, uri, text, shown)
    if first is not None:  # no child needed to say so, and no temporary path in the message
        raise RequestFailed(first)
    try:
        work = scratch.work_folder()
    except OSError as error:
        raise RequestFailed(f"cannot create a temporary folder for the simulation: {error}") from None
    try:
        return await _simulate(ls, uri, text, values, work, shown)
    finally:
        shutil.rmtree(work, ignore_errors=True)


async def _simulate(ls: Any, uri: str, text: str, options: dict[str, str], work: Path,
                    shown: str) -> dict[str, Any]:
    program, report, plot = work / program_name(uri), work / "report.json", work / "plot.png"
    replay = work / "replay.html"
    try:
        program.write_text(text, encoding="utf-8", errors="surrogatepass")  # the simulator refuses those
    except OSError as error:
        raise RequestFailed(f"cannot write the program for the simulator: {error}") from None
    task = asyncio.current_task()
    _cancel_with_request(ls, task)
    progress = _Progress(ls)
    await progress.begin("RDCD simulation", lambda: task.cancel() if task is not None else None)
    try:
        process = await asyncio.create_subprocess_exec(
            *simulate_arguments(program, beside_document(uri, options), report, plot, replay),
            stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
            cwd=str(work), env=child_environment())
    except (OSError, ValueError) as error:
        progress.end("failed")
        raise RequestFailed(f"cannot start the simulator: {error}") from None
    except asyncio.CancelledError:  # while the child starts (asyncio kills it): as below
        progress.end("cancelled")
        raise JsonRpcRequestCancelled("simulation cancelled") from None
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
        # an Exception, not CancelledError: pygls then answers the request instead of forgetting it
        raise JsonRpcRequestCancelled("simulation cancelled") from None
    if process.returncode != 0 or not report.is_file():
        progress.end("failed")
        output = (stderr or stdout).decode("utf-8", "replace")
        raise RequestFailed(first_error(output, program, shown) or f"the simulator ended with status "
                                                                    f"{process.returncode}")
    try:
        result = json.loads(report.read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        progress.end("failed")
        raise RequestFailed(f"cannot read the simulation report: {error}") from None
    try:  # the editor shows them after the working folder is gone
        kept = scratch.keep(uri, "plot", plot) if plot.is_file() else None
        kept_replay = scratch.keep(uri, "replay", replay) if replay.is_file() else None
    except OSError as error:
        progress.end("failed")
        raise RequestFailed(f"cannot keep the simulation's files: {error}") from None
    progress.end("done")
    return {"report": result, "plotPath": str(kept) if kept is not None else None,
            "replayPath": str(kept_replay) if kept_replay is not None else None}


def display_path(uri: str) -> str:
    """The document as the user knows it: its path for a file, else its uri."""
    if uri.startswith("file:"):
        from pygls.uris import to_fs_path

        path = to_fs_path(uri)
        if path:
            return path
    return uri


def program_name(uri: str) -> str:
    """The user's file name for the copy the simulator reads (its messages then name it)."""
    name = uri.rstrip("/").rsplit("/", 1)[-1]
    return name if re.fullmatch(r"[\w.-]{1,100}\.rdcd", name, re.ASCII) else "program.rdcd"


def beside_document(uri: str, options: dict[str, str]) -> dict[str, str]:
    """A relative ``config`` file path read beside the document, as in a terminal in its folder (the
    child runs in its working folder: a user's folder on its path could shadow the simulator's modules)."""
    config = options.get("config")
    if config is None or not uri.startswith("file:") or Path(config).is_absolute():
        return options
    try:
        candidate = Path(display_path(uri)).parent / config
        if candidate.is_file():
            return {**options, "config": str(candidate)}
    except (OSError, ValueError):
        pass
    return options


async def _analysis_of_text(ls: Any, uri: str, text: str) -> Any:
    """The analysis of ``text``, the editor's own one when the open document still holds it (the
    check the diagnostics come from), else one made for ``rdcd.target``; either way in the
    server's worker thread, so the loop goes on answering."""
    from rdcd_core.ide.analysis import analyze

    found = await ls.checked(uri)
    if found is not None and found[0].text == text:
        return found[1]
    return await asyncio.get_running_loop().run_in_executor(
        ls.checker, lambda: analyze(text, target=ls.settings.target))


async def _first_error_in_editor(ls: Any, uri: str, text: str, shown: str) -> str | None:
    """The first error of the text as the editor has it."""
    from rdcd_core.diagnostics import Severity

    analysis = await _analysis_of_text(ls, uri, text)
    error = next((d for d in analysis.diagnostics if d.severity is Severity.ERROR), None)
    if error is None:
        return None
    at = analysis.line_index.line_col(error.span.start)
    return f"{shown}:{at.line + 1}:{at.column + 1}: error[{error.code}]: {_clip(error.message)}"


def first_error(output: str, program: Path, shown: str) -> str | None:
    """The first error the simulator printed, naming the user's file instead of the copy it ran."""
    lines = [line.rstrip() for line in output.replace(str(program), shown).splitlines() if line.strip()]
    for line in lines:
        if line.startswith(shown + ":") and ": error[" in line:
            return _clip(line)
    for line in lines:
        if re.match(r"rdcd( \w+)?: ", line):
            return _clip(line)
    return _clip(lines[-1]) if lines else None


def _clip(text: str, limit: int = 500) -> str:
    return text if len(text) <= limit else f"{text[:limit // 2]} … {text[-limit // 2:]}"


async def bytecode_listing(ls: Any, uri: Any) -> str:
    """The listing of ``rdcd compile --format listing`` for the document as it is in the editor."""
    from rdcd_core.compiler import add_source_lines
    from rdcd_core.compiler.render import render_listing
    from rdcd_core.diagnostics import Severity

    text = _document_text(ls, uri)
    analysis = await _analysis_of_text(ls, uri, text)
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
    async def show_bytecode(ls, *args):  # type: ignore[no-untyped-def]
        return await bytecode_listing(ls, args[0] if args else None)
