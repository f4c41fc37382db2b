"""The key of a run: a hash of everything that determines its result.

Compiled bytes, configuration content, option values, the simulator's parameters (sim/params.py)
and the versions of the code that runs it. Equal keys mean equal runs (the simulation is
deterministic for a seed), so a sweep run again skips every key it already has.
"""

from __future__ import annotations

import hashlib
import json
import platform
from functools import cache
from importlib import metadata
from typing import Any

ROW_FORMAT = 3  # bump when rows change shape or meaning: every run is then done again


@cache
def environment_digest() -> str:
    from rdcd_core import __version__
    from sim import params

    values = {name: getattr(params, name) for name in sorted(dir(params)) if name.isupper()}
    versions = {"rdcd": __version__, "python": platform.python_version(), "row_format": ROW_FORMAT}
    for package in ("pybullet", "numpy"):
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = "none"
    return _digest({"params": values, "versions": versions})


def run_key(program_digest: str, config_digest: str, options: dict[str, Any]) -> str:
    return _digest({"program": program_digest, "config": config_digest,
                    "options": options,
                    "environment": environment_digest()})[:32]


def _digest(content: Any) -> str:
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode("utf-8")).hexdigest()
