"""Shared helpers of the replay tests: a recorded run, and the page's data read back."""

from __future__ import annotations

import base64
import json
import re
import zlib
from typing import Any

import numpy as np

from sim.config import load_config
from sim.replay.recording import Recording
from sim.replay.sources import SourceIndex
from sim.run import Options, simulate
from tests.conftest import EXAMPLES
from tests.sim.helpers import obstacle_program

SOURCE = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")


def recorded_run(world: str, duration: float, config: str = "car7", **options: Any) -> tuple[Recording, dict]:
    program = obstacle_program()
    structure = load_config(config)
    recording = Recording(structure, SourceIndex(program, SOURCE), duration)
    report = simulate(program, structure, Options(world=world, config=config, duration=duration,
                                                  obstacle=options.pop("obstacle", "wall:1.0"),
                                                  recording=recording, **options))
    return recording, report


def page_data(html: str) -> dict[str, Any]:
    found = re.search(r'<script type="application/json" id="rdcd-replay-data">(.*?)</script>', html, re.S)
    assert found, "no data element in the page"
    return json.loads(found.group(1))


def unpack(text: str, rows: int, columns: int) -> np.ndarray:
    """The inverse of sim.replay.encode.packed (what the viewer does in data.js)."""
    if not text:
        return np.zeros((rows, columns), dtype=np.int64)
    raw = np.frombuffer(zlib.decompress(base64.b64decode(text)), dtype="<i4")
    return np.cumsum(raw.reshape(columns, rows).astype(np.int64), axis=1).T
