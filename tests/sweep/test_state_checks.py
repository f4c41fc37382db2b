"""Sweeps whose success tests final state: [success.state] and [success.held_by]
(sim/sweep/state_checks.py), from parsing the experiment file to the verdicts of real lattice runs
of the gradient, the count and the lowest modules."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from rdcd_core.cli import main
from sim.config import load_config
from sim.sweep.experiment import ExperimentError, load
from sim.sweep.state_checks import HeldBy, StateCheck, holds, hop_distances, parse_held_by, parse_state
from tests.conftest import EXAMPLES
from tests.sweep.helpers import experiment, stored_rows


def sweep_text(program: str, success: str, configs: str = '["car7", "snake5", "car8-cyclic"]') -> str:
    return f"""
program = "{EXAMPLES / program}"
[run]
world = "lattice"
obstacle = "none"
duration = 6
[grid]
config = {configs}
packet_loss = [0.0, 0.1]
seed = [1]
[success]
checks = []
bounds = {{ unsettled_states = {{ max = 0 }} }}
{success}
"""


def verdicts(out: Path) -> list[bool]:
    with open(out / "runs.csv", encoding="utf-8") as file:
        return [row["success"] == "True" for row in csv.DictReader(file)]


@pytest.mark.parametrize(("program", "success"), [
    ("gradient.rdcd", '[success.state]\nhops = "hop_distance"'),
    ("count.rdcd", '[success.state]\nsize = { entry = "modules" }'),
    ("lowest.rdcd", '[success.state]\nlowest = "lowest_z"\n[success.held_by]\nBottom = "lowest"'),
])
def test_a_lattice_sweep_of_a_state_example_succeeds_everywhere(tmp_path: Path, program: str,
                                                                 success: str) -> None:
    path = experiment(tmp_path, sweep_text(program, success))
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--workers", "1", "--out", str(out)]) == 0
    rows = stored_rows(out)
    assert len(rows) == 6 and all(r["status"] == "ok" for r in rows.values())
    assert all(r["unsettled_states"] == 0 for r in rows.values())
    assert verdicts(out) == [True] * 6
    page = (out / "index.html").read_text(encoding="utf-8")
    assert {"gradient.rdcd": "every module&#x27;s hops == hop_distance",
            "count.rdcd": "the entry module&#x27;s size == modules",
            "lowest.rdcd": "Bottom held by exactly the lowest modules"}[program] in page


def test_changed_criteria_judge_the_stored_runs_again_without_running_them(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "out"
    right = experiment(tmp_path, sweep_text("count.rdcd", '[success.state]\nsize = { entry = "modules" }',
                                            '["car7", "car11"]'))
    assert main(["sweep", str(right), "--workers", "1", "--out", str(out)]) == 0
    assert verdicts(out) == [True] * 4
    # every module knowing the total is not what count.rdcd does: only the entry module does
    wrong = experiment(tmp_path, sweep_text("count.rdcd", '[success.state]\nsize = "modules"',
                                            '["car7", "car11"]'))
    capsys.readouterr()
    assert main(["sweep", str(wrong), "--workers", "1", "--out", str(out)]) == 0
    assert "0 runs now, 4 before" in capsys.readouterr().out
    assert verdicts(out) == [False] * 4
    seven = experiment(tmp_path, sweep_text("count.rdcd", '[success.state]\nsize = { entry = 7 }',
                                            '["car7", "car11"]'))
    assert main(["sweep", str(seven), "--workers", "1", "--out", str(out)]) == 0
    with open(out / "runs.csv", encoding="utf-8") as file:
        by_config = {(r["config"], r["packet_loss"]): r["success"] == "True" for r in csv.DictReader(file)}
    assert by_config == {("car7", "0.0"): True, ("car7", "0.1"): True,
                         ("car11", "0.0"): False, ("car11", "0.1"): False}


@pytest.mark.parametrize(("success", "problem"), [
    ('[success.state]\nhopz = "hop_distance"', "success.state.hopz: the program has no state 'hopz' "
                                               "(its states: hops)"),
    ('[success.state]\nhops = "distance"', "success.state.hops: must be an integer or one of hop_distance"),
    ('[success.state]\nhops = 300', "success.state.hops: 300 is not a value a state can hold"),
    ('[success.state]\nhops = true', "success.state.hops: must be an integer"),
    ('[success.state]\nhops = { first = 0 }', "success.state.hops: a table must be { entry = V } "
                                                "or { all = V }"),
    ('[success.state]\nhops = { entry = 0, all = 1 }', "a table must be"),
    ('[success]\nstate = 3', "success.state: must be a table"),
    ('[success.held_by]\nTop = "lowest"', "success.held_by.Top: the program has no role 'Top' "
                                            "(its roles: Node)"),
    ('[success.held_by]\nNode = "highest"', "success.held_by.Node: must be one of lowest, entry, all, none"),
])
def test_bad_final_state_criteria_are_one_clear_error(tmp_path: Path, success: str, problem: str) -> None:
    text = sweep_text("gradient.rdcd", "")
    if success.startswith("[success]\n"):  # a key of [success] itself
        text = text.replace("[success]\n", success + "\n", 1)
    else:
        text += success
    with pytest.raises(ExperimentError) as error:
        load(experiment(tmp_path, text))
    assert problem in str(error.value)
    assert "\n" not in str(error.value)


def test_parse_and_judge() -> None:
    checks, problem = parse_state({"hops": "hop_distance", "size": {"entry": "modules"}, "k": -3}, None)
    assert problem is None
    assert checks == (StateCheck("hops", "hop_distance"), StateCheck("size", "modules", "entry"),
                      StateCheck("k", -3))
    held, problem = parse_held_by({"Bottom": "lowest"}, {"Bottom", "Upper"})
    assert problem is None and held == (HeldBy("Bottom", "lowest"),)
    # modules: [id, z, hops, final role, final state]
    final = {"entry": 0, "modules": [[0, 0, 0, "Bottom", {"hops": 0, "size": 3}],
                                     [1, 0, 1, "Bottom", {"hops": 1, "size": 1}],
                                     [2, 1, 2, "Upper", {"hops": 2, "size": 1}]]}
    assert holds(final, checks[:2], held)
    assert not holds(final, (StateCheck("size", "modules"),), ())
    assert not holds(final, (StateCheck("missing", 0),), ())  # a module without the state fails
    assert not holds(final, (), (HeldBy("Upper", "lowest"),))
    assert holds(final, (), (HeldBy("Upper", "none"),)) is False
    assert holds(final, (), (HeldBy("Nobody", "none"),))
    assert holds(final, (StateCheck("size", 3, "entry"),), (HeldBy("Bottom", "lowest"),))
    assert holds(None, (), ())
    assert not holds(None, checks, ())  # a row from before final state was kept


def test_hop_distances_follow_the_connection_graph() -> None:
    car = load_config("car7")
    distances = hop_distances(car)
    assert distances[car.entry] == 0 and set(distances) == set(car.modules)
    snake = load_config("snake5")
    assert sorted(hop_distances(snake).values()) == [0, 1, 2, 3, 4]
