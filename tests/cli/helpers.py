"""Shared helpers of the command-line tests: run the real ``rdcd`` as a child process."""

from __future__ import annotations

import os
import subprocess
import sys

from tests.conftest import ROOT


def rdcd(*args: str, env: dict[str, str] | None = None, **kwargs: object) -> subprocess.CompletedProcess[str]:
    options: dict[str, object] = {"cwd": ROOT, "capture_output": True, "text": True, "timeout": 120,
                                  "env": {**os.environ, **(env or {})}, "errors": "backslashreplace"}
    options.update(kwargs)
    done = subprocess.run([sys.executable, "-m", "rdcd_core", *args], **options)  # type: ignore[call-overload]
    # pybullet prints a banner when `rdcd` imports the simulate subcommand: not ours to judge here
    done.stderr = "".join(line for line in done.stderr.splitlines(keepends=True)
                          if not line.startswith("pybullet build time"))
    return done


def assert_clean_failure(done: subprocess.CompletedProcess[str], status: int, *words: str) -> None:
    """Failed with ``status`` and one line on stderr naming the problem; no traceback."""
    assert done.returncode == status, (done.returncode, done.stdout[-500:], done.stderr[-2000:])
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr, done.stderr
    if status == 2:
        assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    for word in words:
        assert word in done.stderr, done.stderr
