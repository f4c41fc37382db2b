"""From an experiment and its output folder to tasks: the runs of the grid that are still missing."""

from __future__ import annotations

import shlex
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from sim.sweep.experiment import Experiment
from sim.sweep.keys import run_key
from sim.sweep.options import simulate_argv
from sim.sweep.store import Store


def shown(path: Path) -> str:
    """A path as a user would type it here: relative to the current folder when inside it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path.resolve())


class Plan:
    def __init__(self, experiment: Experiment, store: Store, limit: int | None = None) -> None:
        self.experiment = experiment
        self.store = store
        self.total = experiment.size if limit is None else min(limit, experiment.size)
        self.program = shown(experiment.program_path)
        self.config_args = {value: entry.replay for value, entry in experiment.configs.items()}

    def key(self, index: int) -> tuple[str, dict[str, Any]]:
        values = self.experiment.values(index)
        config = self.experiment.configs[values["config"]]
        digest = self.experiment.program_digests[values.get("vm")]
        return run_key(digest, config.digest, values), values

    def keys(self) -> Iterator[str]:
        for index in range(self.total):
            yield self.key(index)[0]

    def task(self, key: str, values: dict[str, Any]) -> dict[str, Any]:
        argv = simulate_argv(self.program, {**values, "config": self.config_args[values["config"]]})
        return {"key": key, "program": self.experiment.program_text,
                "config": self.experiment.configs[values["config"]].data, "options": values,
                "time_limit_s": self.experiment.time_limit_s, "simulate": shlex.join(["rdcd", *argv])}

    def needs(self, key: str, retry_failed: bool) -> bool:
        if not self.store.has(key):
            return True
        return retry_failed and (self.store.read(key) or {}).get("status") != "ok"

    def pending(self, retry_failed: bool = False) -> Iterator[dict[str, Any]]:
        """Tasks of the runs not finished yet, in grid order; computed one at a time."""
        for index in range(self.total):
            key, values = self.key(index)
            if self.needs(key, retry_failed):
                yield self.task(key, values)

    def count_pending(self, retry_failed: bool = False) -> int:
        return sum(1 for key in self.keys() if self.needs(key, retry_failed))
