"""The server's temporary files: one folder per server process, removed when the server ends.

``<tmp>/rdcd-lsp-<pid>-XXXX/`` holds a working folder per running simulation (removed when the
simulation ends, however it ends) and the files the editor's result view shows, the plot and the
replay page: the newest of each kind for each document (an older one of the same document is
removed when a newer one arrives) and at most ``MAX_PLOTS`` of each kind in all. A server that was
killed cannot remove its folder; the next server that simulates removes the folders of servers that
no longer run.
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
SUFFIXES = {"plot": ".png", "replay": ".html"}
_kept: dict[str, dict[str, Path]] = {kind: {} for kind in SUFFIXES}  # kind -> document uri -> newest file


def folder() -> Path:
    global _folder
    if _folder is None or not _folder.is_dir():
        _remove_orphans()
        _folder = Path(tempfile.mkdtemp(prefix=f"{PREFIX}{os.getpid()}-"))
        _forget()
    return _folder


def work_folder() -> Path:
    """A fresh folder for one simulation; the caller removes it."""
    return Path(tempfile.mkdtemp(prefix="run-", dir=folder()))


def keep(uri: str, kind: str, path: Path) -> Path:
    """Moves ``path`` (a ``kind`` of SUFFIXES) out of a working folder; it stays until a newer file
    of that kind of ``uri`` arrives or the server exits."""
    target = folder() / f"{kind}-{uuid.uuid4().hex[:12]}{SUFFIXES[kind]}"
    os.replace(path, target)
    kept = _kept[kind]
    older = kept.pop(uri, None)
    if older is not None:
        older.unlink(missing_ok=True)
    kept[uri] = target
    while len(kept) > MAX_PLOTS:
        oldest = next(iter(kept))
        kept.pop(oldest).unlink(missing_ok=True)
    return target


def _forget() -> None:
    for kept in _kept.values():
        kept.clear()


def remove() -> None:
    global _folder
    if _folder is not None:
        shutil.rmtree(_folder, ignore_errors=True)
    _folder = None
    _forget()


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
