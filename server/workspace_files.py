"""The .rdcd files of the workspace folders that are not open, parsed (cached by mtime) for
workspace symbols."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

from pygls.uris import from_fs_path, to_fs_path

from rdcd_core.ide.analysis import Analysis

log = logging.getLogger("rdcd.server")
MAX_FILES = 500

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


def _parsed(path: Path) -> Analysis | None:
    from rdcd_core.inputs import read_source
    from rdcd_core.syntax.parser import parse

    try:
        mtime = path.stat().st_mtime
        cached = _cache.get(str(path))
        if cached is not None and cached[0] == mtime:
            return cached[1]
        text = read_source(str(path))  # regular files only: a FIFO would block the server
        result = parse(text)
        analysis = Analysis(text, result.program, None, list(result.diagnostics))
        _cache[str(path)] = (mtime, analysis)
        return analysis
    except Exception:
        log.info("cannot read %s for workspace symbols", path)
        return None


def closed_documents(ls: Any, open_uris: set[str]) -> dict[str, Analysis]:
    found: dict[str, Analysis] = {}
    for root in _roots(ls):
        for count, path in enumerate(sorted(root.rglob("*.rdcd"))):
            if count >= MAX_FILES:
                break
            uri = from_fs_path(str(path))
            if uri is None or uri in open_uris or uri in found:
                continue
            analysis = _parsed(path)
            if analysis is not None:
                found[uri] = analysis
    return found
