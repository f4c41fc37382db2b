"""Ctrl-C, as a terminal sends it (SIGINT to the whole foreground process group), during the real
CLI's long jobs: one line on stderr, exit status 130, no traceback, nothing half-written."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.conftest import EXAMPLES, ROOT

sys.path.insert(0, str(ROOT))
from benchmarks.check_speed import generate  # noqa: E402


def interrupted(args: list[str], cwd: Path, ready: Callable[[], bool],
                timeout: float = 120) -> tuple[int, str, str]:
    """Start ``rdcd ARGS`` in its own process group, wait until ``ready()``, send SIGINT to the group."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    process = subprocess.Popen([sys.executable, "-m", "rdcd_core", *args], cwd=cwd, env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                               start_new_session=True)
    try:
        deadline = time.monotonic() + timeout
        while not ready() and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert process.poll() is None, "it ended before it could be interrupted"
        os.killpg(process.pid, signal.SIGINT)
        out, err = process.communicate(timeout=timeout)
    finally:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return process.returncode, out, err


def after(seconds: float) -> Callable[[], bool]:
    start = time.monotonic()
    return lambda: time.monotonic() - start > seconds


def test_ctrl_c_during_a_long_simulation(tmp_path: Path) -> None:
    code, out, err = interrupted(["simulate", str(EXAMPLES / "obstacle_avoidance.rdcd"), "--config", "car11",
                                  "--duration", "3600", "--report", "r.json", "--plot", "p.png"],
                                 tmp_path, after(4))
    assert code == 130
    assert err == "rdcd simulate: interrupted\n"
    assert out == "" and list(tmp_path.iterdir()) == []  # no report, no plot, no temporary file


@pytest.mark.parametrize("command", ["check", "compile"])
def test_ctrl_c_while_checking_a_large_program(tmp_path: Path, command: str) -> None:
    program = tmp_path / "big.rdcd"
    program.write_text(generate(120_000), encoding="utf-8")
    extra = ["-o", "out.json", "--format", "json"] if command == "compile" else []
    code, out, err = interrupted([command, str(program), *extra], tmp_path, after(1.0))
    assert code == 130
    assert err == f"rdcd {command}: interrupted\n"
    assert out == "" and sorted(p.name for p in tmp_path.iterdir()) == ["big.rdcd"]
