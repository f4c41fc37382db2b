"""benchmarks/wheel_loads.py, the measurement behind README's car17-wide note, still runs and
measures: the wheels' ground loads add up to the car's weight while it stands still."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from sim import params

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "wheel_loads.py"


def test_wheel_loads_add_up_to_the_weight(capsys: pytest.CaptureFixture[str]) -> None:
    spec = importlib.util.spec_from_file_location("wheel_loads", SCRIPT)
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--config", "car7", "--obstacle", "none", "--duration", "1", "--every", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header, row = lines[1], lines[2]
    assert header.split("|")[1].split() == ["3", "4", "5", "6"]  # car7's wheels
    loads = [float(cell.rstrip("R")) for cell in row.split("|")[1].split()]
    weight = 7 * params.MODULE_MASS * -params.GRAVITY
    assert sum(loads) == pytest.approx(weight, rel=0.02)
    assert lines[-1].startswith("Reverse spans")  # nothing reversed without an obstacle
