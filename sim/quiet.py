"""PyBullet prints a build-time banner when imported; keep it off the terminal."""

from __future__ import annotations

import ctypes
import importlib
import os
import sys
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def _flush_c() -> None:
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass


def silently(action: Callable[[], T]) -> T:
    """Run ``action`` with file descriptors 1 and 2 on /dev/null (C output included)."""
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:
        return action()
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        result = action()
        _flush_c()
        return result
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)


def import_pybullet() -> None:
    """Import PyBullet for the first time with its banner discarded."""
    if "pybullet" not in sys.modules:
        silently(lambda: importlib.import_module("pybullet"))


def connect(mode: int) -> int:
    import pybullet as pb

    return silently(lambda: pb.connect(mode))
