"""The tutorial's steps do what docs/tutorial.md says they do: checked, compiled and simulated
with the real CLI, from the tutorial's folder as the page tells the reader."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli.helpers import rdcd
from tests.conftest import ROOT

FOLDER = ROOT / "docs" / "tutorial"
PAGE = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")


def run(*args: str) -> str:
    done = rdcd(*args, cwd=FOLDER, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_every_step_is_on_the_page_and_checks_as_it_says() -> None:
    for step in range(1, 5):
        assert f'--8<-- "{FOLDER.relative_to(ROOT)}/step{step}.rdcd"' in PAGE
    assert "1 file checked: 0 errors, 1 warning" in run("check", "step1.rdcd")
    assert "W503" in run("check", "step1.rdcd")
    for step in (2, 3, 4):
        assert run("check", f"step{step}.rdcd").strip() == "1 file checked: no problems"
    assert "discover_RightWheel_LeftWheel 23" in run("simulate", "step2.rdcd", "--config", "two_wheels.json",
                                                     "--world", "lattice", "--duration", "2")


@pytest.mark.parametrize(("step", "collided"), [(3, True), (4, False)])
def test_the_wall_steps_end_as_the_page_shows(tmp_path: Path, step: int, collided: bool) -> None:
    report = tmp_path / "report.json"
    out = run("simulate", f"step{step}.rdcd", "--config", "two_wheels.json", "--obstacle", "wall:0.6",
              "--duration", "30", "--report", str(report))
    for line in out.splitlines()[1:5]:  # roles, fragments, messages, detections: as printed on the page
        assert line in PAGE, line
    result = json.loads(report.read_text(encoding="utf-8"))
    assert result["collided"] is collided
    assert result["obstacle_detections"] >= 1
    heading = result["trajectory"][-1][3]
    assert (abs(heading) > 30) if step == 3 else (abs(heading) < 5)
