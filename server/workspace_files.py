"""The .rdcd files of the workspace folders that are not open, parsed (cached by mtime) for
workspace symbols.

The walk is bounded, so that a root of ``/`` or a home folder cannot hold the server up: it stops
at MAX_FILES programs, after MAX_ENTRIES directory entries or TIME_BUDGET seconds, never goes
deeper than MAX_DEPTH folders, follows no symbolic links to folders, and skips hidden folders,
dependency and build folders and the kernel's pseudo file systems. Files over MAX_FILE_BYTES are
not parsed. The server runs it in a worker thread (``server/views.py``).
"""

from __future__ import annotations

import logging
import os
import stat
import time
from collections import deque
from collections.abc import Iterator
from itertools import islice
from pathlib import Path
from typing import Any

from pygls.uris import from_fs_path, to_fs_path

from rdcd_core.ide.analysis import Analysis

log = logging.getLogger("rdcd.server")
MAX_FILES = 500
MAX_ENTRIES = 20_000  # directory entries looked at, over all roots
MAX_DEPTH = 12
MAX_FILE_BYTES = 2_000_000
TIME_BUDGET = 1.0  # seconds for one walk, parsing included
SKIPPED_FOLDERS = {"node_modules", "__pycache__", "site-packages", "venv", "build", "dist", "target"}
SPECIAL_ROOTS = {"/proc", "/sys", "/dev", "/run"}

_cache: dict[str, tuple[float, Analysis]] = {}


def _roots(ls: Any) -> list[Path]:
    roots: list[Path] = []
    try:
        workspace = ls.workspace
        uris = [folder.uri for folder in workspace.folders.values()]
        if workspace.root_uri:
            uris.append(workspace.root_uri)
    except Exception:
        return roots
    for uri in uris:
        path = to_fs_path(uri) if uri else None
        if path and Path(path).is_dir() and Path(path) not in roots:
            roots.append(Path(path))
    return roots


class Budget:
    """What one walk may still spend: entries looked at and time."""

    def __init__(self, entries: int = MAX_ENTRIES, seconds: float = TIME_BUDGET) -> None:
        self.entries = entries
        self.deadline = time.monotonic() + seconds

    def spend(self) -> bool:
        """Takes one entry; False once the entries or the time are used up."""
        self.entries -= 1
        if self.entries % 64 == 0 and time.monotonic() >= self.deadline:
            self.entries = -1
        return self.entries >= 0

    @property
    def left(self) -> bool:
        return self.entries > 0 and time.monotonic() < self.deadline


def _skipped(entry: os.DirEntry) -> bool:
    return (entry.name.startswith(".") or entry.name in SKIPPED_FOLDERS
            or entry.path in SPECIAL_ROOTS)


def program_files(root: Path, budget: Budget) -> Iterator[Path]:
    """The regular ``*.rdcd`` files under ``root``, breadth first, each folder in name order,
    within ``budget``."""
    folders: deque[tuple[str, int]] = deque([(str(root), 0)])
    while folders:
        folder, depth = folders.popleft()
        try:
            with os.scandir(folder) as listing:  # a folder of a million files is not read whole
                entries = sorted(islice(listing, max(budget.entries, 0) + 1), key=lambda e: e.name)
        except OSError:
            continue  # unreadable: nothing to offer from it
        for entry in entries:
            if not budget.spend():
                return
            try:
                if entry.is_dir(follow_symlinks=False):
                    if depth < MAX_DEPTH and not _skipped(entry):
                        folders.append((entry.path, depth + 1))
                elif entry.name.endswith(".rdcd") and entry.is_file():  # a FIFO would block
                    yield Path(entry.path)
            except OSError:
                continue


def _parsed(path: Path) -> Analysis | None:
    from rdcd_core.inputs import read_source
    from rdcd_core.syntax.parser import parse

    try:
        info = path.stat()
        if not stat.S_ISREG(info.st_mode) or info.st_size > MAX_FILE_BYTES:
            return None
        cached = _cache.get(str(path))
        if cached is not None and cached[0] == info.st_mtime:
            return cached[1]
        text = read_source(str(path))  # regular files only: a FIFO would block the server
        result = parse(text)
        analysis = Analysis(text, result.program, None, list(result.diagnostics))
        _cache[str(path)] = (info.st_mtime, analysis)
        return analysis
    except Exception:
        log.info("cannot read %s for workspace symbols", path)
        return None


def closed_documents(ls: Any, open_uris: set[str], budget: Budget | None = None) -> dict[str, Analysis]:
    budget = budget or Budget()
    found: dict[str, Analysis] = {}
    seen: set[str] = set()
    for root in _roots(ls):
        for path in program_files(root, budget):
            if len(seen) >= MAX_FILES or not budget.left:
                break
            uri = from_fs_path(str(path))
            if uri is None or uri in open_uris or uri in found:
                continue
            seen.add(str(path))
            analysis = _parsed(path)
            if analysis is not None:
                found[uri] = analysis
    if not budget.left:
        log.info("workspace symbols: the walk stopped at its budget; results are partial")
    for stale in set(_cache) - seen:  # the cache holds the files of the latest walk only
        del _cache[stale]
    return found
