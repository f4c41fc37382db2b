"""rdcd simulate --change in the physics world: the same changes, checked the same way, made by
the physics world (sim.reshape)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli.helpers import assert_clean_failure, rdcd

PROGRAM = "examples/lose_a_wheel.rdcd"
PHYSICS = ("--world", "physics", "--duration", "4", "--obstacle", "none")


@pytest.mark.slow
def test_a_wheel_detached_and_a_module_stopped_in_physics(tmp_path: Path) -> None:
    report = tmp_path / "r.json"
    done = rdcd("simulate", PROGRAM, *PHYSICS, "--change", "1s:detach 3", "--change", "2s:stop 5",
                "--report", str(report))
    assert done.returncode == 0, done.stderr
    assert "structure: 2 outside changes" in done.stdout
    data = json.loads(report.read_text())
    assert [(e["module"], e["kind"]) for e in data["events"] if e["kind"].startswith("outside")] == \
        [(3, "outside"), (5, "outside")]
    assert data["parts"] == [[0, 1, 2, 4, 5, 6]]


def test_bad_changes_are_refused_before_a_physics_run() -> None:
    assert_clean_failure(rdcd("simulate", PROGRAM, *PHYSICS, "--change", "9s:detach 3"), 2, "after the end")
    assert_clean_failure(rdcd("simulate", PROGRAM, *PHYSICS, "--change", "1s:attach 9 at 0,0,0"), 2, "taken")
