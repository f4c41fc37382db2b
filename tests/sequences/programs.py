"""Variants of the sequence programs the tests and benchmarks/reconfiguration.py share."""

from __future__ import annotations

import re
from pathlib import Path

HERE = Path(__file__).resolve().parent
# examples/eight_to_car.rdcd's 23 steps alone (no car roles), four pairs as parallel blocks
EIGHT_TO_CAR_STEPS = HERE / "eight_to_car_parallel.rdcd"


def without_blocks(text: str) -> str:
    """The same steps one after the other: the file with its ``parallel {`` and ``}`` lines left out."""
    return re.sub(r"\n  \}\n", "\n", re.sub(r"\n  parallel \{\n", "\n", text))


def with_rollback(text: str) -> str:
    """The program with its (first) sequence marked ``rollback``."""
    changed, count = re.subn(r"^(sequence \w+\(\w+\)) \{", r"\1 rollback {", text, count=1, flags=re.M)
    if not count:
        raise ValueError("no sequence with a starting configuration to mark rollback")
    return changed
