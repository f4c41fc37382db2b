"""Experiment files, the real CLI in a subprocess, and reading an output folder, for sweep tests."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from sim.sweep.rows import MACHINE_FIELDS
from tests.conftest import EXAMPLES, ROOT

PROGRAM = EXAMPLES / "obstacle_avoidance.rdcd"

# The lattice world and short runs keep these tests fast; car7 takes its roles within 8 s.
LATTICE = f"""
program = "{PROGRAM}"
[run]
world = "lattice"
obstacle = "none"
duration = 8
[grid]
config = ["car7", "car11"]
packet_loss = [0.0, 0.3]
seed = {{ from = 1, to = 3 }}
[success]
checks = ["roles"]
"""


def experiment(tmp_path: Path, text: str = LATTICE, name: str = "exp.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def env(**extra: str) -> dict[str, str]:
    paths = [*extra.pop("PYTHONPATH", "").split(os.pathsep), str(ROOT)]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in paths if p), **extra}


def rdcd(*args: str, cwd: Path, timeout: float = 300, **extra_env: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "rdcd_core", *args], cwd=cwd, env=env(**extra_env),
                          capture_output=True, text=True, timeout=timeout, stdin=subprocess.DEVNULL)


def stored_rows(out: Path) -> dict[str, dict]:
    """key -> row of every run file in an output folder."""
    return {p.stem: json.loads(p.read_text(encoding="utf-8")) for p in (out / "runs").glob("*.json")}


def comparable(row: dict) -> dict:
    """A row without what depends on the machine (wall time, host, time of day)."""
    return {k: v for k, v in row.items() if k not in MACHINE_FIELDS}


# Faults injected into every process started with this folder on PYTHONPATH (workers, hosts):
# seed 3 crashes its process, seed 4 hangs in Python, seed 5 raises, seed 6 hangs where no
# signal reaches it (as C code would).
FAULTS = '''
import os, signal, time
if os.environ.get("RDCD_TEST_FAULTS"):
    from sim.quiet import import_pybullet
    import_pybullet()
    import sim.run as _run
    _original = _run.simulate
    def simulate(program, structure, options):
        if options.seed == 3:
            os.kill(os.getpid(), signal.SIGSEGV)
        if options.seed == 4:
            while True:
                time.sleep(0.05)
        if options.seed == 5:
            raise RuntimeError("injected failure")
        if options.seed == 6:
            signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
            time.sleep(3600)
        return _original(program, structure, options)
    _run.simulate = simulate
'''


def fault_folder(tmp_path: Path) -> Path:
    folder = tmp_path / "faults"
    folder.mkdir()
    (folder / "sitecustomize.py").write_text(FAULTS, encoding="utf-8")
    return folder
