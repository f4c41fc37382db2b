"""The recording as compact JSON for the page: numbers quantised, columns delta-coded, deflated.

Poses: an (samples × modules·12) int32 table, differences along time, stored column by column
(each channel of each module in turn), zlib-compressed, base64. Packets: seven int32 columns the
same way (time in ms, sender, receiver, physical connector, size, type, dropped). The viewer
inflates them with the browser's DecompressionStream and sums the differences back.
"""

from __future__ import annotations

import base64
import zlib
from typing import Any

import numpy as np

from sim.replay.recording import CHANNELS, PACKET_KINDS, Recording


def packed(table: np.ndarray) -> str:
    """int32 table (rows × columns) → base64 of zlib of its time differences, column-major."""
    if table.size == 0:
        return ""
    deltas = np.diff(table.astype(np.int64), axis=0, prepend=0).astype("<i4")
    return base64.b64encode(zlib.compress(deltas.T.tobytes(), 9)).decode("ascii")


def poses(recording: Recording) -> dict[str, Any]:
    rows = recording.filled_rows()
    table = np.array(rows, dtype=np.int64).reshape(len(rows), -1)
    times = np.round(np.array(recording.times) * 1000).astype(np.int64).reshape(-1, 1)
    return {"count": len(recording.rows), "channels": CHANNELS,
            "times": packed(times), "data": packed(table)}


def packets(recording: Recording) -> dict[str, Any]:
    rows = [(round(t * 1000), s, r, ch, size, kind, int(dropped))
            for t, s, r, ch, size, kind, dropped in recording.packets]
    table = np.array(rows, dtype=np.int64).reshape(len(rows), 7)
    return {"count": len(rows), "kinds": {str(k): v for k, v in PACKET_KINDS.items()},
            "data": packed(table)}
