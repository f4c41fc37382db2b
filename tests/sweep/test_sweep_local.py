"""`rdcd sweep --workers 1` (in this process, no Dask): rows, tables, resuming, replaying, failures."""

from __future__ import annotations

import csv
import json
import shlex
import time
from pathlib import Path

import pytest

from rdcd_core.cli import main
from sim import sweep
from sim.config import load_config
from sim.sweep.rows import METRICS, measures
from sim.sweep.tables import wilson
from tests.sweep.helpers import LATTICE, comparable, experiment, stored_rows


@pytest.fixture(scope="module")
def finished(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    tmp = tmp_path_factory.mktemp("sweep")
    path = experiment(tmp)
    out = tmp / "out"
    assert main(["sweep", str(path), "--workers", "1", "--out", str(out)]) == 0
    return path, out


def test_every_run_has_a_row_and_the_tables_agree(finished: tuple[Path, Path]) -> None:
    _, out = finished
    rows = stored_rows(out)
    assert len(rows) == 12 and all(r["status"] == "ok" for r in rows.values())
    with open(out / "runs.csv", encoding="utf-8") as file:
        table = list(csv.DictReader(file))
    assert [r["key"] for r in table] == [r["key"] for r in sorted(rows.values(), key=lambda r: (
        ["car7", "car11"].index(r["config"]), r["packet_loss"], r["seed"]))]
    with open(out / "summary.csv", encoding="utf-8") as file:
        cells = list(csv.DictReader(file))
    assert [(c["config"], float(c["packet_loss"]), int(c["runs"])) for c in cells] == [
        ("car7", 0.0, 3), ("car7", 0.3, 3), ("car11", 0.0, 3), ("car11", 0.3, 3)]
    for cell in cells:
        ok = [r for r in table if r["config"] == cell["config"] and float(r["packet_loss"]) ==
              float(cell["packet_loss"]) and r["success"] == "True"]
        assert int(cell["successes"]) == len(ok)
        assert float(cell["ci95_low"]) == pytest.approx(wilson(len(ok), 3)[0])
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "success_vs_packet_loss.png" in page and (out / "success_vs_packet_loss.png").stat().st_size > 1000
    assert (out / "config_obstacle_heatmap.png").is_file()


def test_running_again_runs_nothing(finished: tuple[Path, Path], capsys: pytest.CaptureFixture) -> None:
    path, out = finished
    before = {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()}
    assert main(["sweep", str(path), "--workers", "1", "--out", str(out)]) == 0
    assert "0 runs now, 12 before" in capsys.readouterr().out
    assert before == {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()}


def test_a_row_is_exactly_the_rdcd_simulate_run_it_names(finished: tuple[Path, Path], tmp_path: Path) -> None:
    _, out = finished
    row = next(r for r in stored_rows(out).values() if r["config"] == "car11" and r["packet_loss"] == 0.3)
    argv = shlex.split(row["simulate"])
    assert argv[:2] == ["rdcd", "simulate"]
    report_path = tmp_path / "report.json"
    assert main([*argv[1:], "--report", str(report_path)]) == 0
    report = json.loads(report_path.read_text(encoding="utf-8"))
    replayed = measures(report, load_config("car11"))
    for name in [*METRICS, *(k for k in replayed if k.startswith("check_"))]:
        if name not in ("wall_time_s", "real_time_factor"):
            assert replayed[name] == row[name], name


def test_replay_by_a_shortened_key(finished: tuple[Path, Path], capsys: pytest.CaptureFixture) -> None:
    path, out = finished
    key = next(iter(stored_rows(out)))
    assert main(["sweep", str(path), "--out", str(out), "--replay", key[:10]]) == 0
    assert f"replaying run {key}" in capsys.readouterr().out
    assert main(["sweep", str(path), "--out", str(out), "--replay", "ffffffffff"]) == 2


def test_python_api(finished: tuple[Path, Path]) -> None:
    path, out = finished
    results = sweep.run(sweep.load(path), out=out, workers=1, progress=False)
    assert results.ran == 0 and results.already == 12
    assert len(results.rows()) == 12 and {"success", "key", "simulate"} <= set(results.rows()[0])
    cells = results.summary()
    assert sum(c["runs"] for c in cells) == 12
    assert all(c["ci95_low"] <= (c["success_rate"] or 0) <= c["ci95_high"] for c in cells)
    assert "95% interval" in results.table()


def test_the_summary_says_which_checks_the_runs_missed(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    # 8 s of car7 and car11 with no obstacle: roles are found, nothing is detected, nothing turns
    text = LATTICE.replace("[0.0, 0.3]", "[0.0]").replace("to = 3", "to = 2").replace(
        'checks = ["roles"]', 'checks = ["roles", "detected", "turned"]\nmin_turn_deg = 10\n'
        '[success.bounds]\nmessages_sent = { max = 1 }')
    out = tmp_path / "out"
    assert main(["sweep", str(experiment(tmp_path, text)), "--workers", "1", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    with open(out / "summary.csv", encoding="utf-8") as file:
        cells = list(csv.DictReader(file))
    assert [c["config"] for c in cells] == ["car7", "car11"]
    for cell in cells:
        assert {k: v for k, v in cell.items() if k.startswith("failed_")} == {
            "failed_roles": "0", "failed_detected": "2", "failed_turned": "2", "failed_messages_sent": "2"}
        assert cell["successes"] == "0"
    head, *lines = printed.splitlines()[:3]
    assert head.split()[-2:] == ["missed", "(runs)"]
    assert all(line.endswith("detected 2, turned 2, messages_sent 2") for line in lines)
    page = (out / "index.html").read_text(encoding="utf-8")
    assert page.count("<td>detected 2, turned 2, messages_sent 2</td>") == 2


def test_missed_counts_match_the_rows(finished: tuple[Path, Path]) -> None:
    _, out = finished
    with open(out / "runs.csv", encoding="utf-8") as file:
        table = list(csv.DictReader(file))
    with open(out / "summary.csv", encoding="utf-8") as file:
        cells = list(csv.DictReader(file))
    assert sum(int(c["failed_roles"]) for c in cells) > 0  # 30 % loss in 8 s: some runs miss a role
    for cell in cells:
        mine = [r for r in table if r["config"] == cell["config"]
                and float(r["packet_loss"]) == float(cell["packet_loss"]) and r["status"] == "ok"]
        assert int(cell["failed_roles"]) == sum(r["check_roles"] == "False" for r in mine)
        assert int(cell["failed_roles"]) == int(cell["completed"]) - int(cell["successes"])


def test_wilson_interval_known_values() -> None:
    low, high = wilson(8, 10)
    assert (round(low, 3), round(high, 3)) == (0.490, 0.943)
    assert wilson(0, 10)[0] == 0.0 and round(wilson(0, 10)[1], 3) == 0.278
    assert wilson(0, 0) == (0.0, 1.0)


def test_limit_runs_the_first_runs_of_a_huge_grid(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = experiment(tmp_path, LATTICE.replace("to = 3", "to = 250000000").replace("duration = 8",
                                                                                    "duration = 0.5"))
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--workers", "1", "--out", str(out), "--limit", "3"]) == 0
    rows = stored_rows(out)
    assert sorted(r["seed"] for r in rows.values()) == [1, 2, 3]
    assert "3 runs now" in capsys.readouterr().out


def test_failed_runs_are_rows_and_the_sweep_goes_on(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import sim.run

    original = sim.run.simulate

    def faulty(program, structure, options):  # noqa: ANN001, ANN202
        if options.seed == 4:
            while True:  # a run that never ends
                time.sleep(0.01)
        if options.seed == 5:
            raise RuntimeError("injected failure")
        return original(program, structure, options)

    monkeypatch.setattr(sim.run, "simulate", faulty)
    text = "time_limit_s = 2\n" + LATTICE.replace("from = 1, to = 3", "from = 3, to = 5").replace(
        'config = ["car7", "car11"]', 'config = ["car7"]').replace("[0.0, 0.3]", "[0.0]")
    results = sweep.run(sweep.load(experiment(tmp_path, text)), out=tmp_path / "out", workers=1,
                        progress=False)
    rows = {r["seed"]: r for r in results.rows()}
    assert rows[3]["status"] == "ok"
    assert rows[4]["status"] == "failed" and "exceeded the time limit of 2 s" in rows[4]["error"]
    assert rows[5]["status"] == "failed" and rows[5]["error"] == "RuntimeError: injected failure"
    assert results.summary()[0]["failed"] == 2 and results.failed == 2


def test_outputs_never_overwrite_inputs_or_a_foreign_folder(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture) -> None:
    foreign = tmp_path / "home"
    foreign.mkdir()
    (foreign / "index.html").write_text("mine", encoding="utf-8")
    path = experiment(tmp_path)
    assert main(["sweep", str(path), "--workers", "1", "--out", str(foreign)]) == 2
    assert "not a sweep's output" in capsys.readouterr().err
    assert (foreign / "index.html").read_text(encoding="utf-8") == "mine"
    (foreign / "sweep.json").write_text("{}", encoding="utf-8")  # a sweep's folder ...
    inside = experiment(foreign, LATTICE, name="summary.csv")  # ... holding the experiment itself
    assert main(["sweep", str(inside), "--workers", "1", "--out", str(foreign)]) == 2
    assert "would write over its input" in capsys.readouterr().err
    assert inside.read_text(encoding="utf-8") == LATTICE


def test_parquet_beside_csv(finished: tuple[Path, Path]) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    _, out = finished
    table = pq.read_table(out / "runs.parquet").to_pylist()
    assert len(table) == 12 and table[0]["key"] in stored_rows(out)
    assert isinstance(table[0]["seed"], int) and isinstance(table[0]["success"], bool)


def test_configuration_files_and_random_structures_replay(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    from sim.config import CONFIG_DIR

    car7 = (CONFIG_DIR / "car7.json").read_text(encoding="utf-8")
    (tmp_path / "mine.json").write_text(car7, encoding="utf-8")
    text = LATTICE.replace('config = ["car7", "car11"]', 'config = ["mine.json", "random6-seed2"]').replace(
        "[0.0, 0.3]", "[0.1]").replace("to = 3", "to = 2").replace("duration = 8", "duration = 4")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # the experiment's configuration is found beside it, not here
    out = tmp_path / "out"
    assert main(["sweep", str(experiment(tmp_path, text)), "--workers", "1", "--out", str(out)]) == 0
    rows = stored_rows(out)
    assert len(rows) == 4 and all(r["status"] == "ok" for r in rows.values())
    generated = next(r for r in rows.values() if r["config"] == "random6-seed2")
    # the name itself: `rdcd simulate --config` takes every name a sweep takes
    assert " --config random6-seed2 " in generated["simulate"]
    for row in rows.values():
        report_path = tmp_path / "report.json"
        assert main([*shlex.split(row["simulate"])[1:], "--report", str(report_path)]) == 0
        report = json.loads(report_path.read_text(encoding="utf-8"))
        name = str(tmp_path / "mine.json") if row["config"] == "mine.json" else row["config"]
        structure = load_config(name)
        again = {**row, **measures(report, structure)}
        assert comparable(again) == comparable(row)  # every measure and check, exactly


def test_a_random_physics_run_replays_exactly(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    text = LATTICE.replace('config = ["car7", "car11"]', 'config = ["random12-seed4"]').replace(
        "[0.0, 0.3]", "[0.1]").replace("to = 3", "to = 1").replace("duration = 8", "duration = 3").replace(
        'world = "lattice"', 'world = "physics"').replace('obstacle = "none"', 'obstacle = "wall:0.5"')
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    assert main(["sweep", str(experiment(tmp_path, text)), "--workers", "1", "--out", str(out)]) == 0
    (row,) = stored_rows(out).values()
    assert row["status"] == "ok" and row["messages_sent"] > 0
    report_path = tmp_path / "report.json"
    assert main([*shlex.split(row["simulate"])[1:], "--report", str(report_path)]) == 0
    report = json.loads(report_path.read_text(encoding="utf-8"))
    assert report["config"] == "random12-seed4"
    assert comparable({**row, **measures(report, load_config("random12-seed4"))}) == comparable(row)


def test_summary_prints_what_is_done_and_runs_nothing(finished: tuple[Path, Path],
                                                      capsys: pytest.CaptureFixture) -> None:
    path, out = finished
    before = sorted(p.name for p in (out / "runs").iterdir())
    assert main(["sweep", str(path), "--out", str(out), "--summary"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split()[:3] == ["config", "packet_loss", "runs"] and len(lines) == 5
    assert sorted(p.name for p in (out / "runs").iterdir()) == before
