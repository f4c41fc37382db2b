"""The compact form of a ``rollback`` sequence (rdcd_core/sequences/compact.py): the table holds
the undo of step k at progress 2n - 1 - k (the last step's never runs, and is not there), and a
failed step k sets 2n - k, the ordinary form's numbering (docs/reconfiguration.md "Rolling back
from a program"). examples/car_to_snake.rdcd with
``rollback`` does not fit the program slots in the ordinary form; in tables it does, reaches the
snake, and rolls back to car7 when a step's latch fails."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from rdcd_core.sequences.compact import UNDO_GAP, applies, role_table
from rdcd_core.sequences.lower import lower, ordered_steps
from rdcd_core.syntax.parser import parse
from sim.config import load_config
from sim.run import Options, simulate
from tests.sequences.programs import EIGHT_TO_CAR_STEPS, with_rollback, without_blocks
from tests.sequences.shapes import shape, structure_shape
from vm.lattice.outside import parse_all

ROOT = Path(__file__).resolve().parents[2]
CAR = with_rollback((ROOT / "examples" / "car_to_snake.rdcd").read_text())
N = 12  # carToSnake's steps: 2n = 24 is "rolled back"


def _sequence(steps: str, modifier: str = "rollback"):  # noqa: ANN202 - the parsed program
    text = f"role R {{ self.x() >= 0; }}\nsequence s {modifier} {{ {steps} }}\ndeployment {{ R }}\n"
    return parse(text).program


def test_the_table_holds_each_step_at_k_and_its_undo_at_2n_minus_1_minus_k() -> None:
    program = _sequence("R(self.x() == 1).disconnect(2); R(self.x() == 2).turnQuarters(1);")
    sequence = program.sequences[0]
    assert applies(sequence)
    read, startup, acts = role_table("s", ordered_steps(sequence), "R", False, rollback=True)
    # n = 2: forward at 0, 1 (1*14+2, 2*14+12); 2 (done) is 0; the undo of step 0 at 3
    # (connect(2): 1*14+6); 4 is "rolled back", outside. The last step's undo is not there: a
    # failure after the last step cannot happen
    assert read == "s_t := table(s, 16, 40, 0, 20) - s_k;"
    assert startup == "s_k := (self.x()) * 14;"
    # a failed step k (S < n, S_t still its code) sets 2n - k; a failed undo is read again
    assert [a[0] for a in acts] == [
        "behavior s_t_R() { if (self.act(s_t)) { s := s + 1; s_t := 0; } "
        "if (s_t > 0 && s_t < 14 && s < 2) { s := 4 - s; s_t := 0; } }"]


def test_backwards_the_table_swaps_steps_and_undos() -> None:
    program = _sequence("R(self.x() == 1).disconnect(2); R(self.x() == 2).turnQuarters(1);")
    sequence = program.sequences[0]
    read, _, _ = role_table("s", ordered_steps(sequence, True), "R", True, rollback=True)
    # reversed: the undo of step 1 (turn -1) then of step 0 (connect(2)); the first one's own undo
    # after (turn +1)
    assert read == "s_t := table(s, 38, 20, 0, 40) - s_k;"


def test_far_apart_the_forward_and_undo_entries_are_two_tables() -> None:
    steps = "R(self.x() == 1).connect(0); " + "R.waitUntil(1 == 1); " * (UNDO_GAP + 2)
    sequence = _sequence(steps).sequences[0]
    read, _, _ = role_table("s", ordered_steps(sequence), "R", False, rollback=True)
    n = UNDO_GAP + 3  # step 0 at 0, its undo at 2n - 1: 2n - 2 zeros between cost more than a table
    assert read == f"s_t := table(s, 19) - s_k; s_t := s_t + table(s - {2 * n - 1}, 15);"
    steps = "R(self.x() == 1).connect(0); R.waitUntil(1 == 1);"  # 2 zeros between: one table
    read, _, _ = role_table("s", ordered_steps(_sequence(steps).sequences[0]), "R", False, True)
    assert read == "s_t := table(s, 19, 0, 0, 15) - s_k;"


def test_without_rollback_nothing_changes() -> None:
    program = _sequence("R(self.x() == 1).disconnect(2); R(self.x() == 2).turnQuarters(1);", "")
    read, _, acts = role_table("s", ordered_steps(program.sequences[0]), "R", False)
    assert read == "s_t := table(s, 16, 40) - s_k;" and "s_t > 0" not in acts[0][0]


def test_the_compact_rollback_lowering_has_no_step_behaviours() -> None:
    program = _sequence("R(self.x() == 1).disconnect(2); R(self.x() == 2).turnQuarters(1);")
    lowered = lower(program, compact=True)
    members = [m.name.text for m in lowered.roles[0].members if hasattr(m, "name")]
    assert members == ["s_relay", "s_k_R", "s_t_R"]


def test_a_parallel_block_of_a_rollback_sequence_runs_one_step_after_the_other_in_tables() -> None:
    program = _sequence("parallel { R(self.x() == 1).disconnect(2); R(self.x() == 2).disconnect(4); }")
    sequence = program.sequences[0]
    assert applies(sequence) and not applies(_sequence(  # without rollback: blocks of two (a lane)
        "parallel { R(self.x() == 1).disconnect(2); R(self.x() == 2).disconnect(4); "
        "R(self.x() == 3).disconnect(4); }", "").sequences[0])
    read, _, _ = role_table("s", ordered_steps(sequence), "R", False, rollback=True)
    assert read == "s_t := table(s, 16, 31, 0, 20) - s_k;"  # no bitmask: steps 0, 1, step 0's undo
    names = [s.name.text for s in lower(program, compact=True).states]
    assert names == ["s", "s_t", "s_k"]  # no s_par


def _compiled():  # noqa: ANN202 - the checked result and the program
    result = check_text(CAR)
    assert result.diagnostics == [], result.diagnostics
    program = compile_model(result.model, text=CAR)
    return result, program


def test_car_to_snake_with_rollback_fits_in_tables() -> None:
    result, program = _compiled()
    assert not program.has_errors and program.diagnostics == []  # no W601
    assert len(program.fragments) <= 10 and all(f.size <= 43 for f in program.fragments)
    assert any(s.name == "carToSnake_t" for s in program.states)


def _run(changes: list[str], *, loss: float = 0.0, seed: int = 0) -> dict:
    _, program = _compiled()
    options = Options(world="lattice", config="car7", obstacle="none", duration=90, seed=seed,
                      packet_loss=loss, outside_changes=parse_all(changes))
    return simulate(program, load_config("car7"), options)


def test_without_a_fault_it_reaches_the_snake() -> None:
    result, _ = _compiled()
    report = _run([])
    assert shape(report) == structure_shape(result.traces[0].final)
    assert {m["final_state"]["carToSnake"] for m in report["modules"]} == {N}


@pytest.mark.parametrize("fault, loss, seed", [
    ("0s:fail 3 6", 0.0, 0),  # step 1's latch: step 0 undone
    ("0s:fail 6 4", 0.0, 0),  # step 8's latch: steps 7..0 undone
    ("0s:fail 6 4", 0.2, 1),
])
def test_a_failed_latch_rolls_back_to_the_car(fault: str, loss: float, seed: int) -> None:
    report = _run([fault], loss=loss, seed=seed)
    assert "connect_failed" in [e["kind"] for e in report["events"]]
    assert shape(report) == structure_shape(load_config("car7"))
    assert {m["final_state"]["carToSnake"] for m in report["modules"]} == {2 * N}


def test_backwards_with_rollback_gives_the_car_back() -> None:
    # --reverse-sequence on a rollback sequence: the undos forward, the steps as their undos
    from rdcd_core.sequences.roles import vm_frames

    result = check_text(CAR)
    trace = result.traces[0]
    program = compile_model(result.model, text=CAR, reverse="carToSnake")
    assert not program.has_errors and program.diagnostics == [] and len(program.fragments) <= 10
    options = Options(world="lattice", config="car7", obstacle="none", duration=90, seed=0,
                      frames=vm_frames(trace.learned))
    report = simulate(program, trace.final.copy(), options)
    assert shape(report) == structure_shape(load_config("car7"))
    assert {m["final_state"]["carToSnake"] for m in report["modules"]} == {N}


def test_the_simulator_says_rolled_back(tmp_path: Path) -> None:
    from tests.cli.helpers import rdcd

    path = tmp_path / "car_to_snake_rollback.rdcd"
    path.write_text(CAR)
    done = rdcd("simulate", str(path), "--world", "lattice", "--obstacle", "none", "--config", "car7",
                "--duration", "60", "--change", "0s:fail 3 6")
    assert done.returncode == 0 and "sequence carToSnake: rolled back" in done.stdout, done.stderr


def test_a_rollback_sequence_that_fits_neither_form_gets_the_ordinary_error_and_why_tables_failed() -> None:
    # eight_to_car with rollback and its car: E121 in the form it is written in, and the tables'
    # own error: the relay's three parts, the act's two and the car's roles take 11 fragments
    text = with_rollback((ROOT / "examples" / "eight_to_car.rdcd").read_text())
    result = check_text(text)
    program = compile_model(result.model, text=text)
    assert not program.fragments and program.has_errors
    assert {d.code for d in program.diagnostics} == {"E121"}
    assert all("the steps as tables (the compact form) do not fit either (E805: with its sequences the "
               "program compiles to 11 fragments" in d.message for d in program.diagnostics)


# ------------------------------------------------------------- eight_to_car's steps alone, rollback

EIGHT_TO_CAR = with_rollback(without_blocks(EIGHT_TO_CAR_STEPS.read_text()))
STEPS = 23


def test_eight_to_cars_steps_with_rollback_fit_in_tables() -> None:
    # 23 steps and 22 undos: 46 entries in three relay parts (9, 18 and 19), the act and its
    # failure statement in two; five command numbers
    result = check_text(EIGHT_TO_CAR)
    assert result.diagnostics == [], result.diagnostics
    program = compile_model(result.model, text=EIGHT_TO_CAR)
    assert not program.has_errors and program.diagnostics == []
    assert len(program.fragments) == 6 and all(f.size <= 43 for f in program.fragments)


def _eight_to_car_run(changes: list[str], loss: float = 0.0, seed: int = 0) -> dict:
    result = check_text(EIGHT_TO_CAR)
    program = compile_model(result.model, text=EIGHT_TO_CAR)
    options = Options(world="lattice", config="eight7", obstacle="none", duration=150, seed=seed,
                      packet_loss=loss, outside_changes=parse_all(changes))
    return simulate(program, load_config("eight7"), options)


def test_eight_to_cars_steps_with_rollback_reach_the_car() -> None:
    report = _eight_to_car_run([])
    assert shape(report) == structure_shape(check_text(EIGHT_TO_CAR).traces[0].final)
    assert {m["final_state"]["eightToCar"] for m in report["modules"]} == {STEPS}


@pytest.mark.parametrize("fault, loss, seed", [
    ("0s:fail 6 6", 0.0, 0),  # step 15 (module 6 latches its connector 6): steps 14..0 undone
    ("0s:jam 2 0", 0.1, 3),  # step 20 (module 2 unlatches its connector 0): steps 19..0 undone
])
def test_eight_to_cars_steps_roll_back_to_the_eight(fault: str, loss: float, seed: int) -> None:
    report = _eight_to_car_run([fault], loss, seed)
    assert shape(report) == structure_shape(load_config("eight7"))
    assert {m["final_state"]["eightToCar"] for m in report["modules"]} == {2 * STEPS}
