"""The experiment file: the shipped example and robustness experiment load; every kind of bad
file is one line naming the file and the key, exit status 2, and nothing runs."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.cli import main
from sim.sweep import ExperimentError, load
from sim.sweep.cli import EXAMPLE
from sim.sweep.grid import Axis, Grid, range_axis
from tests.conftest import EXAMPLES, ROOT
from tests.sweep.helpers import LATTICE, PROGRAM, experiment


def test_shipped_robustness_experiment_is_the_issue_grid() -> None:
    e = load(ROOT / "experiments" / "robustness.toml")
    assert e.grid.names == ["config", "packet_loss", "seed"]
    assert e.size == 120
    assert [e.values(i)["config"] for i in (0, 40, 80)] == ["car7", "car11", "car8-cyclic"]
    assert sorted({e.values(i)["packet_loss"] for i in range(120)}) == [0.0, 0.1, 0.2, 0.3]
    assert e.fixed["world"] == "physics" and e.fixed["duration"] == 60.0


def test_init_writes_the_example_and_its_program_which_load(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture) -> None:
    target = tmp_path / "new.toml"
    assert main(["sweep", "--init", str(target)]) == 0
    assert target.read_text(encoding="utf-8") == EXAMPLE.read_text(encoding="utf-8")
    program = tmp_path / "obstacle_avoidance.rdcd"
    assert program.read_bytes() == (EXAMPLES / "obstacle_avoidance.rdcd").read_bytes()
    assert f"wrote {target} and its program {program}" in capsys.readouterr().out
    e = load(target)
    assert e.size == 12 and e.checks[0] == "detected"
    assert e.fixed["duration"] == 60.0  # long enough to be driving forward again at the end
    assert e.bounds == {"min_obstacle_distance_m": (0.01, None)}


def test_the_example_cites_only_what_the_repository_has() -> None:
    from tests.docs.references import dangling

    text = EXAMPLE.read_text(encoding="utf-8")
    assert list(dangling("sim/sweep/example.toml", text)) == []
    assert "docs/simulator.md" in text and (ROOT / "docs" / "simulator.md").is_file()


def test_init_twice_in_a_folder_shares_the_program(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["sweep", "--init", str(tmp_path / "a.toml")]) == 0
    assert main(["sweep", "--init", str(tmp_path / "b.toml")]) == 0
    assert "its program: the existing" in capsys.readouterr().out
    assert load(tmp_path / "b.toml").program_path == tmp_path / "obstacle_avoidance.rdcd"


def test_init_never_overwrites(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    target = tmp_path / "mine.toml"
    target.write_text("precious", encoding="utf-8")
    assert main(["sweep", "--init", str(target)]) == 2
    assert target.read_text(encoding="utf-8") == "precious"
    assert "exists" in capsys.readouterr().err
    assert not (tmp_path / "obstacle_avoidance.rdcd").exists()  # all or nothing


def test_init_never_replaces_another_program(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    mine = tmp_path / "obstacle_avoidance.rdcd"
    mine.write_text("role Mine { }\ndeployment { Mine }\n", encoding="utf-8")
    assert main(["sweep", "--init", str(tmp_path / "new.toml")]) == 2
    assert "is not the example program" in capsys.readouterr().err
    assert mine.read_text(encoding="utf-8").startswith("role Mine")
    assert not (tmp_path / "new.toml").exists()


BAD = [
    ("unknown top key", 'colour = "red"\n' + LATTICE, "colour: unknown key"),
    ("unknown grid key", LATTICE.replace("[grid]", "[grid]\nspeed = [1]"), "grid.speed: unknown key"),
    ("unknown run key", LATTICE.replace("[run]", "[run]\ngui = true"), "run.gui: unknown key"),
    ("wrong type", LATTICE.replace("packet_loss = [0.0, 0.3]", 'packet_loss = ["a lot"]'),
     "grid.packet_loss[0]: must be a number, not a string"),
    ("bool for a number", LATTICE.replace("duration = 8", "duration = true"),
     "run.duration: must be a number"),
    ("empty axis", LATTICE.replace('config = ["car7", "car11"]', "config = []"), "grid.config: empty list"),
    ("empty grid", LATTICE.split("[grid]")[0], "grid: empty"),
    ("missing program", LATTICE.replace(f'program = "{PROGRAM}"', ""), "program: missing"),
    ("program not found", LATTICE.replace(str(PROGRAM), "nowhere.rdcd"), "program: no such file"),
    ("program with errors", LATTICE.replace(str(PROGRAM), str(EXAMPLES / "figure5_verbatim.rdcd")),
     "program: the program has errors: "),
    ("unknown configuration", LATTICE.replace('"car11"', '"car99"'),
     "grid.config: car99: no such configuration"),
    ("bad obstacle", LATTICE.replace('obstacle = "none"', 'obstacle = "moat:3"'), "run: "),
    ("loss out of range", LATTICE.replace("[0.0, 0.3]", "[0.0, 1.5]"),
     "grid.packet_loss: --packet-loss must be"),
    ("reversed range", LATTICE.replace("from = 1, to = 3", "from = 3, to = 1"), "grid.seed: empty range"),
    ("range without to", LATTICE.replace("from = 1, to = 3", "from = 1"), "grid.seed: a range needs"),
    ("zero step", LATTICE.replace("to = 3", "to = 3, step = 0"), "grid.seed.step: must be positive"),
    ("range of strings", LATTICE.replace('config = ["car7", "car11"]', "config = { from = 1, to = 2 }"),
     "grid.config: must be a list"),
    ("in run and grid", LATTICE.replace("[run]", "[run]\nseed = 1"), "run.seed: also an axis"),
    ("unknown check", LATTICE.replace('checks = ["roles"]', 'checks = ["flies"]'),
     "success.checks[0]: unknown"),
    ("unknown measure", LATTICE + "[success.bounds]\nspeed = { min = 1 }\n", "success.bounds.speed: unknown"),
    ("bad bound", LATTICE + "[success.bounds]\ndistance_m = 3\n", "success.bounds.distance_m: must be"),
    ("bad world", LATTICE.replace('"lattice"', '"moon"'), "run.world: 'moon' is not one of"),
    ("not TOML", "program = \n", "not valid TOML"),
    ("grid not a table", "grid = 3\n" + LATTICE.split("[grid]")[0], "grid: must be a table"),
    ("bad time limit", "time_limit_s = -1\n" + LATTICE, "time_limit_s: must be a positive number"),
]


@pytest.mark.parametrize(("text", "expected"), [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_experiment_is_one_line_exit_2_and_nothing_runs(tmp_path: Path, text: str, expected: str,
                                                            capsys: pytest.CaptureFixture,
                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    path = experiment(tmp_path, text)
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", str(path), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"rdcd sweep: {path}: "), err
    assert expected in err, err
    assert not (tmp_path / "exp-sweep").exists()
    with pytest.raises(ExperimentError):
        load(path)


def test_missing_and_directory_experiment_files(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["sweep", str(tmp_path / "none.toml")]) == 2
    assert main(["sweep", str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert "no such file" in err[0] and "directory" in err[1]


@pytest.mark.parametrize(("args", "expected"), [
    (["--workers", "0"], "--workers must be in 1..1024"),
    (["--limit", "0"], "--limit must be at least 1"),
    (["--workers", "2", "--scheduler", "tcp://x:1"], "give one of them"),
    (["--scheduler", "nowhere"], "give an address"),
])
def test_bad_options(tmp_path: Path, args: list[str], expected: str, capsys: pytest.CaptureFixture) -> None:
    assert main(["sweep", str(experiment(tmp_path)), *args]) == 2
    assert expected in capsys.readouterr().err


def test_a_grid_of_a_billion_runs_is_refused_without_being_built(tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture) -> None:
    path = experiment(tmp_path, LATTICE.replace("to = 3", "to = 250000000"))
    e = load(path)  # a range is never enumerated: loading is instant
    assert e.size == 1_000_000_000
    assert e.values(e.size - 1) == {**e.values(0), "config": "car11", "packet_loss": 0.3, "seed": 250000000}
    assert main(["sweep", str(path), "--workers", "1", "--out", str(tmp_path / "o")]) == 2
    assert "1,000,000,000 runs" in capsys.readouterr().err and not (tmp_path / "o").exists()


@given(st.lists(st.lists(st.integers(), min_size=1, max_size=4), min_size=1, max_size=4))
def test_grid_points_are_the_product_in_order(values: list[list[int]]) -> None:
    grid = Grid(tuple(Axis(f"a{i}", tuple(v)) for i, v in enumerate(values)))
    assert grid.size == len(list(itertools.product(*values)))
    assert [tuple(p.values()) for p in grid.points()] == list(itertools.product(*values))


@given(st.integers(-50, 50), st.integers(0, 60), st.integers(1, 7))
def test_integer_ranges_include_both_ends(start: int, span: int, step: int) -> None:
    axis = range_axis("seed", start, start + span, step, integer=True)
    assert [axis[i] for i in range(len(axis))] == list(range(start, start + span + 1, step))


def test_float_ranges_give_the_values_a_user_reads() -> None:
    axis = range_axis("packet_loss", 0.0, 0.3, 0.1, integer=False)
    assert [axis[i] for i in range(len(axis))] == [0.0, 0.1, 0.2, 0.3]
