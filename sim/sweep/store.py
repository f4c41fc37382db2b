"""The output folder of a sweep: one JSON file per finished run, written the moment it finishes.

    OUT/sweep.json          marks the folder as a sweep's (and says which experiment last used it)
    OUT/runs/KEY.json       one row per run, written atomically: nothing finished is ever lost
    OUT/runs.csv, runs.parquet, summary.csv, *.png, index.html   regenerated from the rows

A folder that exists, is not empty and has no sweep.json is refused: it is someone's, not ours.
"""

from __future__ import annotations

import json
import os
import re
import tempfile
from pathlib import Path
from typing import Any

from rdcd_core.outputs import write_atomically

MARKER = "sweep.json"
GENERATED = ("runs.csv", "runs.parquet", "summary.csv", "index.html", MARKER)
_KEY = re.compile(r"[0-9a-f]{6,64}")


class StoreError(ValueError):
    """An output folder that cannot be used; one line."""


class Store:
    def __init__(self, root: Path) -> None:
        self.root = root
        self.runs = root / "runs"
        self.configs = root / "configs"

    @classmethod
    def open(cls, root: Path, inputs: list[Path], about: dict[str, Any]) -> Store:
        """Create or reuse ``root`` for a sweep; refuse one that is not a sweep's, or that would
        put an output where an input is."""
        store = cls(root)
        if root.exists() and not root.is_dir():
            raise StoreError(f"{root}: exists and is not a folder; choose another --out")
        if root.is_dir() and any(root.iterdir()) and not (root / MARKER).is_file():
            raise StoreError(f"{root}: a folder that is not a sweep's output (no {MARKER}) and not empty; "
                             "choose another --out")
        for path in inputs:
            if store.would_overwrite(path):
                raise StoreError(f"{root}: the sweep would write over its input {path}; choose another --out")
        try:
            store.runs.mkdir(parents=True, exist_ok=True)
            write_atomically(str(root / MARKER), json.dumps(about, indent=1) + "\n")
        except OSError as error:
            raise StoreError(f"{root}: cannot write: {error.strerror or error}") from None
        return store

    def would_overwrite(self, path: Path) -> bool:
        try:
            resolved, root = path.resolve(), self.root.resolve()
        except OSError:
            return False
        if resolved.parent == root:
            return resolved.name in GENERATED or resolved.suffix == ".png"
        return resolved.parent in (root / "runs", root / "configs")

    def path(self, key: str) -> Path:
        return self.runs / f"{key}.json"

    def has(self, key: str) -> bool:
        return self.path(key).is_file()

    def read(self, key: str) -> dict[str, Any] | None:
        """The row of ``key``, or None if it has not run (or its file is not a row: run it again)."""
        try:
            row = json.loads(self.path(key).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        return row if isinstance(row, dict) and row.get("key") == key else None

    def write(self, row: dict[str, Any]) -> None:
        write_atomically(str(self.path(row["key"])), json.dumps(row, sort_keys=True) + "\n")

    def find(self, prefix: str) -> list[str]:
        """Keys of finished runs starting with ``prefix`` (a key can be given shortened)."""
        if not _KEY.fullmatch(prefix):
            return []
        return sorted(p.stem for p in self.runs.glob(f"{prefix}*.json"))


def replace_with(path: Path, write: Any) -> None:
    """Write a file through ``write(temporary_path)`` and rename it into place (atomic): for
    writers that must open the file themselves (pyarrow's ParquetWriter closes its sink); every
    other output goes through ``rdcd_core.outputs``."""
    fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(temporary)
        os.replace(temporary, path)
    except BaseException:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        raise
