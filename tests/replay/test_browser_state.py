"""The replay page shows a module's state values over time (real headless Chromium): click a module,
and its panel gives each state's value at the time shown — what the JSON report's history says —,
a sparkline of its history and the changes up to now; a role state only while its role is played."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli.helpers import rdcd
from tests.replay.browser import need_browser, probe

# the lowest modules, with a role state that only Bottom has (and counts up a little)
ROLE_STATE = """\
state lowest := 127;
abstract role Node {
  behavior spread() {
    lowest := min(min(neighbours.lowest), self.z());
  }
}
role Bottom extends Node {
  state visits := 3;
  self.z() == lowest;
  behavior count() { if (visits < 9) visits := visits + 1; }
}
role Upper extends Node { }
deployment { Bottom, Upper }
"""


def run(tmp_path: Path, program: Path) -> tuple[Path, dict]:
    page, report = tmp_path / "run.html", tmp_path / "run.json"
    done = rdcd("simulate", str(program), "--world", "lattice", "--config", "car7", "--obstacle", "none",
                "--duration", "4", "--replay", str(page), "--report", str(report))
    assert done.returncode == 0, done.stderr
    return page, json.loads(report.read_text())


def role_at(module: dict, t: float) -> str | None:
    role = None
    for time, name in module["role_history"]:
        if time <= t + 1e-9:
            role = name
    return role


def expected(report: dict, module: dict, t: float) -> dict[str, int | None]:
    """The values the page must show at t, from the report alone."""
    role = role_at(module, t)
    values: dict[str, int | None] = {}
    for state in report["states"]:
        values[state["name"]] = 0 if state["owner"] is None or role in state["roles"] else None
    for time, name, value in module["state_history"]:
        if time <= t + 1e-9 and values[name] is not None:
            values[name] = value
    return values


@pytest.fixture(scope="module")
def role_state_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    need_browser()
    folder = tmp_path_factory.mktemp("state")
    source = folder / "lowest_visits.rdcd"
    source.write_text(ROLE_STATE, encoding="utf-8")
    return run(folder, source)


def test_clicking_a_module_shows_its_state_values_over_time(role_state_run: tuple[Path, dict]) -> None:
    page, report = role_state_run
    # module 0 is Bottom for a moment, then Upper: its role state comes and goes
    module = next(m for m in report["modules"] if len(m["role_history"]) >= 3)
    changes = [t for t, _, _ in module["state_history"]]
    roles = [t for t, _ in module["role_history"]]
    times = sorted({0.0, 4.0, *changes, *(t + 0.005 for t in changes), *roles})
    result = probe(page, module=module["id"], moduleTime=0.0, stateTimes=times)
    assert result["ready"] == "true", result.get("error")
    assert result["console"] == [] and result["pageErrors"] == [] and result["csp"] == []
    assert result["moduleVisible"]
    assert "State at 0.00 s" in result["modulePanel"]
    shown_visits = False
    for shown in result["states"]:
        want = expected(report, module, shown["t"])
        assert shown["values"] == want, shown["t"]
        panel = shown["panel"]
        assert f"State at {shown['t']:.2f} s" in panel
        assert f"lowest{want['lowest']}" in panel
        if want["visits"] is None:
            assert "visits— (only in Bottom)" in panel
        else:
            shown_visits = True
            assert f"visits{want['visits']}" in panel
        assert shown["sparklines"] == 2  # one per state that ever changed
    assert shown_visits, "the module never showed its role state"
    last = result["states"][-1]
    assert last["t"] == 4.0
    assert {k: v for k, v in last["values"].items() if v is not None} == module["final_state"]
    for t, name, value in module["state_history"][-5:]:
        assert f"{t:.2f} s {name} = {value}" in last["panel"]


def test_a_module_that_keeps_its_role_state_ends_with_the_reported_values(
        role_state_run: tuple[Path, dict]) -> None:
    page, report = role_state_run
    module = next(m for m in report["modules"] if m["final_role"] == "Bottom")
    result = probe(page, module=module["id"], moduleTime=4.0, stateTimes=[4.0])
    assert result["ready"] == "true"
    [last] = result["states"]
    assert last["values"] == module["final_state"]
    assert set(module["final_state"]) == {"lowest", "visits"} and module["final_state"]["lowest"] == -2
    assert f"visits{module['final_state']['visits']}" in last["panel"]


def test_a_program_without_state_shows_no_state_section(tmp_path: Path) -> None:
    need_browser()
    from tests.conftest import EXAMPLES

    page, report = run(tmp_path, EXAMPLES / "obstacle_avoidance.rdcd")
    assert report["states"] == []
    result = probe(page, module=report["modules"][1]["id"], moduleTime=1.0, stateTimes=[1.0])
    assert result["ready"] == "true"
    assert "State at" not in result["modulePanel"]
    assert result["states"][0]["panel"] is None and result["states"][0]["values"] == {}
