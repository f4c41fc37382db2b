"""Sequences run in the lattice world as rdcd simulate runs them: the final structure equals the
shape the checker finds at the end (cells and connections), with and without lost packets; the
sequence run backwards gives the start back; 100 % loss ends at the run's duration with the
structure unchanged."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from rdcd_core.sequences.roles import vm_frames
from sim.config import load_config
from sim.run import Options, simulate
from tests.sequences.shapes import shape, structure_shape

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EIGHT = (EXAMPLES / "eight_to_snake.rdcd").read_text()


def run(text: str, config: str, *, loss: float = 0.0, seed: int = 0, duration: float = 40.0,
        reverse: str | None = None) -> tuple[dict, object]:
    result = check_text(text)
    assert not result.has_errors, result.diagnostics
    start = load_config(config)
    if reverse is not None:
        start = result.traces[0].final
    program = compile_model(result.model, text=text, reverse=reverse)
    assert not program.has_errors, program.diagnostics
    # backwards: the robot as the forward run leaves it, each module in the frame it learned
    frames = vm_frames(result.traces[0].learned) if reverse is not None else {}
    options = Options(world="lattice", config=config, obstacle="none", duration=duration, seed=seed,
                      packet_loss=loss, frames=frames)
    return simulate(program, start, options), result.traces[0]


def test_eight_to_snake_ends_in_the_checked_shape() -> None:
    report, trace = run(EIGHT, "eight7")
    assert shape(report) == structure_shape(trace.final)
    assert report["modules"][0]["final_state"]["eightToSnake"] == 2


@pytest.mark.parametrize("loss, seed", [(0.1, 1), (0.2, 2), (0.3, 3), (0.3, 4)])
def test_lost_packets_delay_but_never_break_it(loss: float, seed: int) -> None:
    report, trace = run(EIGHT, "eight7", loss=loss, seed=seed, duration=60)
    assert report["messages"]["dropped"] > 0
    assert shape(report) == structure_shape(trace.final)


def test_run_backwards_it_gives_the_eight_back() -> None:
    report, _ = run(EIGHT, "eight7", reverse="eightToSnake", loss=0.2, seed=5, duration=60)
    assert shape(report) == structure_shape(load_config("eight7"))


def test_all_packets_lost_ends_at_the_duration_with_nothing_done() -> None:
    report, _ = run(EIGHT, "eight7", loss=1.0, duration=5)
    assert report["duration_s"] == 5
    assert shape(report) == structure_shape(load_config("eight7"))


def test_the_new_shape_s_work_waits_for_the_end_of_the_sequence() -> None:
    # a role of the snake (an NS module inside the chain) whose behaviour is gated by the progress
    text = "state working := 0;\n" + EIGHT.replace("role Hub {", """role Spine {
  self.center_position == NORTH_SOUTH;
  sizeof(self.total_connected()) == 2;
  behavior work() {
    if (eightToSnake == 2) {
      working := 1;
    }
  }
}

role Hub {""").replace("deployment { UpperLeft, LowerRight, Hub, Side }",
                       "deployment { UpperLeft, LowerRight, Spine, Hub, Side }")
    report, trace = run(text, "eight7")
    assert shape(report) == structure_shape(trace.final)
    modules = {m["id"]: m for m in report["modules"]}
    assert [modules[m]["final_role"] for m in (0, 3, 6)] == ["Spine"] * 3
    assert [modules[m]["final_state"]["working"] for m in (0, 3, 6)] == [1, 1, 1]
    done = max(e["t"] for e in report["events"] if e["kind"] == "disconnect")
    for m in (0, 3, 6):  # no work before the last step
        changes = [entry for entry in modules[m]["state_history"] if "working" in str(entry)]
        assert changes, modules[m]["state_history"]
        assert all(entry[0] >= done for entry in changes), changes


@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 7)])
def test_a_failed_step_rolls_back_to_the_start(loss: float, seed: int) -> None:
    text = (Path(__file__).parent / "rollback.rdcd").read_text()
    result = check_text(text)
    assert [d.code for d in result.diagnostics] == ["W810"]
    program = compile_model(result.model, text=text)
    assert not program.has_errors and max(f.size for f in program.fragments) <= 43
    options = Options(world="lattice", config="eight7", obstacle="none", duration=40, seed=seed,
                      packet_loss=loss)
    report = simulate(program, load_config("eight7"), options)
    kinds = [e["kind"] for e in report["events"] if e["kind"] in ("connect", "disconnect", "connect_failed")]
    assert kinds[0] == "disconnect" and "connect_failed" in kinds and kinds[-1] == "connect"
    assert shape(report) == structure_shape(load_config("eight7"))
    assert {m["final_state"]["s"] for m in report["modules"]} == {4}  # 2n: rolled back


def test_the_command_line_says_how_far_the_sequence_got(tmp_path: Path) -> None:
    import subprocess
    import sys

    program = EXAMPLES / "eight_to_snake.rdcd"
    common = [sys.executable, "-m", "rdcd_core", "simulate", str(program), "--config", "eight7",
              "--world", "lattice", "--obstacle", "none", "--duration", "8"]
    lost = subprocess.run([*common, "--packet-loss", "1"], capture_output=True, text=True, timeout=300)
    assert lost.returncode == 0 and "sequence eightToSnake: not done: 0 of 2 steps" in lost.stdout
    done = subprocess.run(common, capture_output=True, text=True, timeout=300)
    assert "sequence eightToSnake: done" in done.stdout
    back = subprocess.run([*common, "--reverse-sequence", "eightToSnake"], capture_output=True, text=True,
                          timeout=300)
    assert "sequence eightToSnake backwards: done" in back.stdout
    bad = subprocess.run([*common, "--reverse-sequence", "nope"], capture_output=True, text=True, timeout=300)
    assert bad.returncode != 0 and "no sequence of that name" in bad.stderr and "Traceback" not in bad.stderr


def test_at_80_percent_loss_it_only_takes_longer() -> None:
    # issue 24: every run ends in the target shape at every loss below 100 %, only later. A link
    # sends a program, a notify or a value again for as long as its neighbour is attached (before,
    # it gave up after 12 tries, and this run stopped at the first step for good, from 71 s on)
    report, trace = run(EIGHT, "eight7", loss=0.8, seed=0, duration=900)
    assert shape(report) == structure_shape(trace.final)
    assert all(m["final_state"]["eightToSnake"] == 2 for m in report["modules"])
