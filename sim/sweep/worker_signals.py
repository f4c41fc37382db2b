"""Preloaded into the worker processes of the local cluster (``LocalCluster(preload=...)``).

Ctrl-C in a terminal reaches every process of the foreground process group. The driver is the
one that handles it (it stops submitting, keeps every finished run and closes the cluster); a
worker process that took it too would print Dask's KeyboardInterrupt traceback while it dies.
"""

from __future__ import annotations

import signal
from typing import Any


def dask_setup(worker: Any) -> None:  # noqa: ARG001 - Dask's preload interface
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread of its process: nothing to change there
        pass
