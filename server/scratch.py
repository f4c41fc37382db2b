"""The server's temporary files: one folder per server process, removed when the server ends.

``<tmp>/rdcd-lsp-<pid>-XXXX/`` holds a working folder per running simulation (removed when the
simulation ends, however it ends) and the plots the editor's result view shows: the newest plot of
each document (an older one of the same document is removed when a newer one arrives) and at most
``MAX_PLOTS`` in all. A server that was killed cannot remove its folder; the next server that
simulates removes the folders of servers that no longer run.
"""

from __future__ import annotations

import logging
import os
import re
import shutil
import tempfile
import uuid
from pathlib import Path

log = logging.getLogger("rdcd.server")

PREFIX = "rdcd-lsp-"
MAX_PLOTS = 16
_OURS = re.compile(re.escape(PREFIX) + r"(\d+)-")

_folder: Path | None = None
_plots: dict[str, Path] = {}  # document uri -> its newest plot, oldest first


def folder() -> Path:
    global _folder
    if _folder is None or not _folder.is_dir():
        _remove_orphans()
        _folder = Path(tempfile.mkdtemp(prefix=f"{PREFIX}{os.getpid()}-"))
        _plots.clear()
    return _folder


def work_folder() -> Path:
    """A fresh folder for one simulation; the caller removes it."""
    return Path(tempfile.mkdtemp(prefix="run-", dir=folder()))


def keep_plot(uri: str, plot: Path) -> Path:
    """Moves ``plot`` out of a working folder; it stays until a newer plot of ``uri`` or the exit."""
    target = folder() / f"plot-{uuid.uuid4().hex[:12]}.png"
    os.replace(plot, target)
    older = _plots.pop(uri, None)
    if older is not None:
        older.unlink(missing_ok=True)
    _plots[uri] = target
    while len(_plots) > MAX_PLOTS:
        oldest = next(iter(_plots))
        _plots.pop(oldest).unlink(missing_ok=True)
    return target


def remove() -> None:
    global _folder
    if _folder is not None:
        shutil.rmtree(_folder, ignore_errors=True)
    _folder = None
    _plots.clear()


def _remove_orphans() -> None:
    """Folders of our own servers whose process is gone (killed: they could not clean up)."""
    try:
        entries = list(Path(tempfile.gettempdir()).iterdir())
    except OSError:
        return
    for entry in entries:
        match = _OURS.match(entry.name)
        if match is None or int(match.group(1)) == os.getpid() or _running(int(match.group(1))):
            continue
        try:
            info = entry.lstat()
        except OSError:
            continue
        if entry.is_dir() and not entry.is_symlink() and info.st_uid == _uid(info.st_uid):
            log.info("removing %s, left by a server that no longer runs", entry)
            shutil.rmtree(entry, ignore_errors=True)


def _uid(default: int) -> int:
    getuid = getattr(os, "getuid", None)  # not on Windows
    return getuid() if getuid is not None else default


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True  # someone else's process, or a number we cannot ask about: leave it alone
    return True
