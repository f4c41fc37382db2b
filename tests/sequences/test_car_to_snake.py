"""examples/car_to_snake.rdcd: car7 lies down into a flat chain of seven (eleven of the twelve
steps the lattice planner finds, vm/lattice/plan.py, none opening a link between two male
connectors); one role with keys, compiled to tables (the compact form). The lattice world ends
in the shape the checker finds, with and without lost packets, and the sequence run backwards on
the robot as the forward run leaves it gives the car back: same cells, same connections."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from rdcd_core.sequences.check import backwards
from rdcd_core.sequences.roles import vm_frames
from sim.config import load_config
from sim.run import Options, simulate
from tests.sequences.shapes import shape, structure_shape
from vm.isa.opcodes import BUILTIN_COMMANDS, ROTATE_CCW, ROTATE_CW, STOP
from vm.lattice.plan import FlatChain

TEXT = (Path(__file__).resolve().parents[2] / "examples" / "car_to_snake.rdcd").read_text()


def run(*, loss: float = 0.0, seed: int = 0, reverse: bool = False) -> tuple[dict, object]:
    result = check_text(TEXT)
    assert not result.diagnostics, result.diagnostics
    trace = result.traces[0]
    start = trace.final if reverse else load_config("car7")
    program = compile_model(result.model, text=TEXT, reverse="carToSnake" if reverse else None)
    assert not program.has_errors and len(program.fragments) <= 10
    assert all(f.size <= 43 for f in program.fragments)
    options = Options(world="lattice", config="car7", obstacle="none", duration=60, seed=seed,
                      packet_loss=loss, frames=vm_frames(trace.learned) if reverse else {})
    return simulate(program, start.copy(), options), trace


def test_checks_clean_and_ends_in_a_flat_chain() -> None:
    result = check_text(TEXT)
    assert result.diagnostics == []
    final = result.traces[0].final
    assert FlatChain(7).reached(final) and len(final.parts()) == 1


def test_one_role_by_keys_compiles_to_tables_within_the_program_slots() -> None:
    # eleven steps over five acting modules: a role per module needs at least eleven fragments
    result = check_text(TEXT)
    program = compile_model(result.model, text=TEXT)
    assert not program.has_errors and len(program.fragments) <= 10
    assert any(b == 80 for f in program.fragments for b in f.code)  # TABLE


@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 1), (0.2, 2)])
def test_the_lattice_world_ends_in_the_checked_chain(loss: float, seed: int) -> None:
    report, trace = run(loss=loss, seed=seed)
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["carToSnake"] for m in report["modules"]} == {12}  # every module heard


def test_backwards_the_checker_gives_the_car_back() -> None:
    result = check_text(TEXT)
    trace = backwards(result.model, result.program.sequences[0], result.traces[0])
    assert trace.diagnostics == []
    assert structure_shape(trace.final) == structure_shape(load_config("car7"))
    assert [r.module for r in trace.results] == [r.module for r in reversed(result.traces[0].results)]


@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 3)])
def test_run_backwards_it_gives_the_car_back_same_cells_same_connections(loss: float, seed: int) -> None:
    report, _ = run(reverse=True, loss=loss, seed=seed)
    assert shape(report) == structure_shape(load_config("car7"))


def done_at(report: dict) -> float:
    """When the first module heard that the sequence is done."""
    return min(t for m in report["modules"] for t, name, value in m["state_history"]
               if name == "carToSnake" and value == 12)


def moved_after_done(report: dict) -> tuple[float, float]:
    """How far the robot's centre moved (net) from ``done_at`` to the end of the run, and in how
    many seconds."""
    path = [p for p in report["trajectory"] if p[0] >= done_at(report)]
    return math.dist(path[0][1:3], path[-1][1:3]), path[-1][0] - path[0][0]


@pytest.mark.slow
@pytest.mark.parametrize("reverse", [False, True])
def test_the_physics_world_reaches_the_chain_which_crawls_and_gives_the_car_back(reverse: bool) -> None:
    # backwards, every module starts in the frame it learned in the car (Options.frames): the
    # physics world holds them as the lattice world does
    result = check_text(TEXT)
    trace = result.traces[0]
    program = compile_model(result.model, text=TEXT, reverse="carToSnake" if reverse else None)
    options = Options(world="physics", config="car7", obstacle="none", duration=60, seed=0,
                      frames=vm_frames(trace.learned) if reverse else {})
    report = simulate(program, (trace.final if reverse else load_config("car7")).copy(), options)
    goal = load_config("car7") if reverse else trace.final
    assert shape(report) == structure_shape(goal)
    moved, seconds = moved_after_done(report)
    assert seconds > 40
    if reverse:  # the car given back: only the driver has two connections, and it does not roll
        assert moved < 0.02
    else:  # the chain crawls (3.7 m in the 57 s of a 70 s run, benchmarks/reconfiguration.py --crawl)
        assert moved > 2.0


def test_once_the_sequence_is_done_the_chains_inner_modules_roll_as_the_table_says() -> None:
    # lattice world: a wheel's turn moves no structure there, but the commands show who rolls and
    # which way: modules 3 and 6 clockwise, modules 1, 2 and 5 counter-clockwise; the
    # ends of the chain (0 and 4) do nothing
    report, _ = run()
    done = done_at(report)
    turns = (ROTATE_CW, ROTATE_CCW, STOP)
    rolls = {e["module"]: BUILTIN_COMMANDS[e["detail"]["command"]] for e in report["events"]
             if e["kind"] == "command" and e["t"] >= done and e["detail"]["command"] in turns}
    assert rolls == {1: "ROTATE_CCW", 2: "ROTATE_CCW", 3: "ROTATE_CW", 5: "ROTATE_CCW", 6: "ROTATE_CW"}


@pytest.mark.parametrize("config, name, said", [
    ("eight7", "carToSnake", "cannot be run forward from eight7"),  # the keys name no module there
    ("car7", "nope", "no sequence of that name"),
    ("no-such-config", "carToSnake", "no-such-config")])
def test_the_command_line_refuses_a_reversal_it_cannot_start(config: str, name: str, said: str,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    from rdcd_core.cli import main

    path = str(Path(__file__).resolve().parents[2] / "examples" / "car_to_snake.rdcd")
    assert main(["simulate", path, "--config", config, "--world", "lattice", "--obstacle", "none",
                 "--duration", "5", "--reverse-sequence", name]) == 2
    err = capsys.readouterr().err
    assert said in err and "Traceback" not in err and err.count("\n") == 1
