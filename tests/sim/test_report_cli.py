"""Report schema, summary, plot and the `rdcd simulate` command line (lattice world: fast)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from rdcd_core.cli import main
from sim.config import load_config
from sim.obstacles import ObstacleError, parse_obstacle
from sim.plot import plot_report
from sim.report import heading_change, summary
from sim.run import Options, simulate
from sim.scenario import forward_at_end, judge_straight
from tests.conftest import EXAMPLES
from tests.sim.helpers import obstacle_program

PROGRAM = str(EXAMPLES / "obstacle_avoidance.rdcd")
MODULE_KEYS = {"id", "lattice", "orientation", "final_lattice", "final_orientation", "final_mount",
               "final_role", "final_state", "state_history",
               "state_history_omitted", "role_history", "errors"}
TOP_KEYS = {"world", "config", "duration_s", "seed", "wall_time_s", "real_time_factor", "modules",
            "fragments", "messages", "events", "trajectory", "obstacle_detections", "min_obstacle_distance_m",
            "collided", "entry", "states", "settle_window_s", "unsettled"}


@pytest.fixture(scope="module")
def lattice_report() -> dict:
    structure = load_config("car11")
    return simulate(obstacle_program(), structure, Options(world="lattice", config="car11", duration=10.0))


def test_lattice_report_schema_and_roles(lattice_report: dict) -> None:
    assert TOP_KEYS <= set(lattice_report)
    json.dumps(lattice_report)
    assert lattice_report["world"] == "lattice" and lattice_report["trajectory"] == []
    assert lattice_report["collided"] is None and lattice_report["min_obstacle_distance_m"] is None
    structure = load_config("car11")
    for m in lattice_report["modules"]:
        assert set(m) == MODULE_KEYS
        assert m["orientation"] in ("NS", "EW", "UD")
        assert m["final_role"] == structure.expected_roles[m["id"]]
    assert {f["name"] for f in lattice_report["fragments"]} == {f.name for f in obstacle_program().fragments}
    assert lattice_report["messages"]["delivered"] > 0
    assert "roles:" in summary(lattice_report)


def test_heading_change_wraps() -> None:
    traj = [[0.0, 0, 0, 170.0], [1.0, 0, 0, -170.0]]
    assert heading_change(traj) == pytest.approx(20.0)
    assert heading_change([]) is None


def test_forward_at_end_uses_the_heading() -> None:
    north = [[t, 0.0, 0.06 * t, 0.0] for t in range(10)]
    assert forward_at_end({"trajectory": north})
    west_backwards = [[t, 0.06 * t, 0.0, 90.0] for t in range(10)]  # heading west, moving east
    assert not forward_at_end({"trajectory": west_backwards})


def test_plot_of_a_physics_like_report(tmp_path: Path, lattice_report: dict) -> None:
    report = dict(lattice_report, world="physics", obstacle="wall:1.0", collided=False,
                  obstacles=[{"kind": "wall", "x": 0.0, "y": 1.025, "w": 3.0, "l": 0.05}],
                  trajectory=[[t / 10, 0.0, t / 100, 0.5 * t] for t in range(100)],
                  events=[{"t": 5.0, "module": 3, "kind": "handler", "detail": {"event": 5}}])
    out = tmp_path / "car.png"
    plot_report(report, None, str(out))
    assert out.stat().st_size < 200_000 and out.read_bytes()[:4] == b"\x89PNG"
    assert judge_straight(report, load_config("car11"))["straight"] is False


@pytest.mark.parametrize("spec,boxes",
                         [("none", 0), ("wall:1.0", 1), ("box:0.5,1,0.2,0.3", 1), ("WALL:2", 1)])
def test_obstacle_specs(spec: str, boxes: int) -> None:
    assert len(parse_obstacle(spec)) == boxes


@pytest.mark.parametrize("spec", ["wall", "wall:-1", "box:1,2", "box:1,2,0,1", "tree:3", "none:1", "wall:x"])
def test_bad_obstacle_specs(spec: str) -> None:
    with pytest.raises(ObstacleError):
        parse_obstacle(spec)


def _cli(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    status = main(["simulate", *args])
    out, err = capsys.readouterr()
    return status, out, err


@pytest.mark.parametrize("args,fragment", [
    (["missing.rdcd"], "no such file"),
    ([PROGRAM, "--config", "car99"], "car99"),
    ([PROGRAM, "--obstacle", "wall:"], "--obstacle"),
    ([PROGRAM, "--duration", "0"], "--duration"),
    ([PROGRAM, "--packet-loss", "2"], "--packet-loss"),
    ([PROGRAM, "--world", "lattice", "--record", "x.gif"], "physics world"),
    ([PROGRAM, "--report", "/no/such/dir/r.json"], "does not exist"),
])
def test_cli_usage_errors_exit_2(capsys: pytest.CaptureFixture[str], args: list[str], fragment: str) -> None:
    status, out, err = _cli(capsys, *args)
    assert status == 2
    assert fragment in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_cli_gui_without_display(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    status, _, err = _cli(capsys, PROGRAM, "--gui")
    assert status == 2 and "display" in err


def test_cli_broken_config_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text('{"modules": [{"id": 0, "position": [1, 0, 0], "axis": "NS"}]}', encoding="utf-8")
    status, _, err = _cli(capsys, PROGRAM, "--config", str(bad))
    assert status == 2 and "bad.json" in err and len(err.strip().splitlines()) == 1


def test_cli_program_errors_exit_1(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    bad = tmp_path / "bad.rdcd"
    bad.write_text("role A {\n  self.center_position == EAST_WST;\n}\ndeployment { A }\n", encoding="utf-8")
    status, _, err = _cli(capsys, str(bad), "--world", "lattice")
    assert status == 1 and "bad.rdcd" in err


def test_cli_lattice_run_writes_report_and_plot(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    report, plot = tmp_path / "r.json", tmp_path / "p.png"
    status, out, _ = _cli(capsys, PROGRAM, "--world", "lattice", "--duration", "5", "--config", "car7",
                          "--report", str(report), "--plot", str(plot))
    assert status == 0, out
    data = json.loads(report.read_text(encoding="utf-8"))
    assert data["config"] == "car7" and plot.exists()
    assert "2 × Axle" in out
