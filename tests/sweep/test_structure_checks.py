"""Sweeps with outside changes as a dimension and success judged on the final structure
([success.structure], sim/sweep/structure_checks.py): parsing, the shape comparison up to a turn
and a shift, the verdicts of real lattice runs, and bad input refused before any run."""

from __future__ import annotations

import csv
import json
import shlex
from pathlib import Path

import pytest

from rdcd_core.cli import main
from sim.config import load_config
from sim.sweep.experiment import ExperimentError, load
from sim.sweep.structure_checks import ROTATIONS, Shape, failures, parse_structure, shape_of
from tests.conftest import EXAMPLES
from tests.sweep.helpers import experiment, stored_rows


def sweep_text(grid: str = 'changes = [[], ["20s:detach 3"], "20s:detach 1"]',
               structure: str = 'shape = "car7"\nparts = 1\nconnected = [[0, 1], [1, 3]]',
               duration: float = 22) -> str:
    return f"""
program = "{EXAMPLES / 'lose_a_wheel.rdcd'}"
[run]
world = "lattice"
obstacle = "none"
duration = {duration}
config = "car7"
[grid]
{grid}
seed = [1]
[success]
checks = []
[success.structure]
{structure}
"""


def summary_rows(out: Path) -> list[dict[str, str]]:
    with open(out / "summary.csv", encoding="utf-8") as file:
        return list(csv.DictReader(file))


def test_a_sweep_over_outside_changes_counts_each_structure_check_it_misses(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert main(["sweep", str(experiment(tmp_path, sweep_text())), "--workers", "1", "--out", str(out)]) == 0
    rows = sorted(stored_rows(out).values(), key=lambda r: r["changes"])
    assert [r["changes"] for r in rows] == ["", "20s:detach 1", "20s:detach 3"]
    assert all(r["status"] == "ok" for r in rows)
    assert [r["final"]["parts"] for r in rows] == [1, 3, 1]
    assert [len(r["final"]["cells"]) for r in rows] == [7, 6, 6]
    cells = {r["changes"]: r for r in summary_rows(out)}
    assert cells[""]["successes"] == "1"
    assert {k: v for k, v in cells["20s:detach 3"].items() if k.startswith("failed_")} == {
        "failed_structure_shape": "1", "failed_structure_parts": "0", "failed_structure_connected": "1"}
    assert cells["20s:detach 1"]["failed_structure_parts"] == "1"
    # the run's command replays it, changes included
    command = shlex.split(next(r for r in rows if r["changes"] == "20s:detach 3")["simulate"])
    assert command[-2:] == ["--change", "20s:detach 3"]
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "the final structure has car7&#x27;s shape" in page
    assert "2 of them" not in page


def test_the_replay_command_of_a_row_gives_the_same_structure(tmp_path: Path) -> None:
    out = tmp_path / "out"
    text = sweep_text(grid='changes = [["20s:detach 1"]]')
    assert main(["sweep", str(experiment(tmp_path, text)), "--workers", "1", "--out", str(out)]) == 0
    row = next(iter(stored_rows(out).values()))
    report = tmp_path / "r.json"
    argv = shlex.split(row["simulate"])[1:]
    assert main([*argv, "--report", str(report)]) == 0
    data = json.loads(report.read_text(encoding="utf-8"))
    assert sorted(m["id"] for m in data["modules"] if m["final_lattice"] is not None) == \
        sorted(c[0] for c in row["final"]["cells"])
    assert len(data["parts"]) == row["final"]["parts"] == 3


def test_changes_in_run_apply_to_every_run_and_change_the_key(tmp_path: Path) -> None:
    plain = load(experiment(tmp_path, sweep_text(grid="packet_loss = [0.0]"), "a.toml"))
    text = sweep_text(grid="packet_loss = [0.0]").replace('config = "car7"', 'config = "car7"\n'
                                                          'changes = "20s:detach 3"')
    changed = load(experiment(tmp_path, text, "b.toml"))
    assert plain.values(0)["changes"] == "" and changed.values(0)["changes"] == "20s:detach 3"
    from sim.sweep.plan import Plan
    from sim.sweep.store import Store

    keys = {Plan(e, Store(tmp_path / name)).key(0)[0] for e, name in ((plain, "a"), (changed, "b"))}
    assert len(keys) == 2


@pytest.mark.parametrize(("grid", "message"), [
    ('changes = [["20s:detach 99"]]', "grid.changes[0]: on car7: change '20s:detach 99': no module 99"),
    ('changes = [[], ["30s:detach 3"]]', "grid.changes[1]: on car7: change '30s:detach 3': at 30 s, after"),
    ('changes = [["20s:explode 3"]]', "grid.changes[0]: change '20s:explode 3': unknown change 'explode'"),
    ('changes = [["20s:attach 9 at 0,0,0"]]', "cell (0, 0, 0) is taken by module 0"),
    ('changes = [["20s:detach 3", 5]]', "a list of change texts"),
    ('changes = [["20s:detach 3; 21s:detach 4"]]', "one change per string"),
    ('changes = []', "grid.changes: must be a non-empty list"),
    ('changes = 3', "grid.changes: must be a non-empty list"),
    ('changes = [["20s:detach 3"], ["20s:detach 3", "21s:detach 3"]]', "no module 3 (detached before)"),
    ('changes = [["0s:detach 0"]]', "change '0s:detach 0'"),  # the entry module stays
])
def test_bad_changes_are_refused_before_any_run(tmp_path: Path, grid: str, message: str) -> None:
    with pytest.raises(ExperimentError) as error:
        load(experiment(tmp_path, sweep_text(grid=grid)))
    assert message in str(error.value)
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(("structure", "message"), [
    ('shape = "car99"', "success.structure.shape:"),
    ("shape = 7", "success.structure.shape: must name a configuration"),
    ("parts = 0", "success.structure.parts: must be a whole number from 1"),
    ("modules = true", "success.structure.modules: must be a whole number"),
    ("connected = [[1, 1]]", "success.structure.connected: must be a list of module pairs"),
    ("connected = [[1, 2, 3]]", "must be a list of module pairs"),
    ("connected = []", "must be a list of module pairs"),
    ("colour = 3", "success.structure.colour: unknown key (known: shape, parts, modules, connected)"),
])
def test_bad_structure_checks_are_refused(tmp_path: Path, structure: str, message: str) -> None:
    with pytest.raises(ExperimentError) as error:
        load(experiment(tmp_path, sweep_text(structure=structure)))
    assert message in str(error.value) and "\n" not in str(error.value)


def test_a_structure_table_that_is_not_a_table_is_refused(tmp_path: Path) -> None:
    text = sweep_text(structure="").replace("[success.structure]\n", "structure = 3\n")
    with pytest.raises(ExperimentError, match="success.structure: must be a table"):
        load(experiment(tmp_path, text))


def _facts(structure, entry_shift=(0, 0, 0), turn=None) -> dict:  # noqa: ANN001
    cells = []
    for m, spec in structure.modules.items():
        c = spec.position
        if turn is not None:
            c = tuple(sum(turn[i][j] * c[j] for j in range(3)) for i in range(3))
        cells.append([m, *(c[i] + entry_shift[i] for i in range(3))])
    return {"entry": structure.entry, "cells": cells, "parts": len(structure.parts()),
            "links": sorted({(min(k.a, k.b), max(k.a, k.b)) for k in structure.links()})}


@pytest.mark.parametrize("config", ["car7", "car11", "snake5", "random12-seed3"])
def test_a_shape_is_the_same_after_any_turn_and_shift(config: str) -> None:
    structure = load_config(config)
    check, problem = parse_structure({"shape": config}, lambda name: shape_of(load_config(name), name))
    assert problem is None
    for turn in ROTATIONS:
        assert failures(_facts(structure, (4, -2, 6), turn), check) == []


def test_a_different_shape_or_other_links_fail() -> None:
    car7 = shape_of(load_config("car7"), "car7")
    check, _ = parse_structure({"shape": "car7"}, lambda name: car7)
    assert failures(_facts(load_config("car11")), check) == ["structure_shape"]
    facts = _facts(load_config("car7"))
    facts["links"] = facts["links"][1:]
    assert failures(facts, check) == ["structure_shape"]
    moved = _facts(load_config("car7"))
    moved["cells"][-1][3] += 2  # one module on another cell
    assert failures(moved, check) == ["structure_shape"]


def test_old_rows_without_structure_facts_miss_every_structure_check() -> None:
    checks, _ = parse_structure({"parts": 1, "modules": 7}, lambda name: Shape(name, (0, 0, 0),
                                                                                frozenset(), frozenset()))
    assert failures({"entry": 0, "modules": []}, checks) == ["structure_parts", "structure_modules"]
    assert failures(None, checks) == ["structure_parts", "structure_modules"]
    assert failures(None, ()) == []
