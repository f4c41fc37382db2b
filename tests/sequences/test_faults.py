"""Faults put in from outside (vm/lattice/outside.py): ``jam ID C`` (the latch of connector C no
longer moves) and ``fail ID C`` (it does not close the next time, once). With ``rollback`` a
sequence whose step meets such a fault ends in its start shape, never in between; bad faults are
refused before the run, one line, never a traceback."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import Options, simulate
from tests.cli.helpers import assert_clean_failure, rdcd
from tests.sequences.shapes import shape, structure_shape
from vm.lattice.outside import ChangeError, OutsideChange, parse, parse_all, validate

HERE = Path(__file__).parent
RELATCH = (HERE / "relatch.rdcd").read_text()
LATTICE = ("--world", "lattice", "--duration", "30", "--obstacle", "none", "--config", "eight7")


def run(text: str, changes: list[str], *, loss: float = 0.0, seed: int = 0) -> tuple[dict, object]:
    result = check_text(text)
    assert not result.has_errors, result.diagnostics
    program = compile_model(result.model, text=text)
    assert not program.has_errors, program.diagnostics
    options = Options(world="lattice", config="eight7", obstacle="none", duration=40, seed=seed,
                      packet_loss=loss, outside_changes=parse_all(changes))
    return simulate(program, load_config("eight7"), options), result.traces[0]


def test_the_forms() -> None:
    assert parse("0s:jam 2 0") == OutsideChange(0.0, "jam", 2, text="0s:jam 2 0", connector=0)
    assert parse(" 1.5 : fail 4 6 ").connector == 6
    assert parse("3:fail 4 6").describe() == "fail 4 6"


@pytest.mark.parametrize("text", [
    "0s:jam 2", "0s:jam 2 8", "0s:jam 2 -1", "0s:fail 2 x", "0s:jam 2 0 1", "0s:fail 2 at 1,1,0",
    "0s:jam 2 00", "0s:jam 2 0 close", "0s:jam", "0s:fail 2 99999999999999999999", "jam 2 0",
])
def test_bad_faults_are_one_line_errors(text: str) -> None:
    with pytest.raises(ChangeError) as caught:
        parse(text)
    message = str(caught.value)
    assert "\n" not in message and ("connector 0..7" in message or "TIME" in message), message


@pytest.mark.parametrize("text, words", [
    ("0s:jam 99 0", "no module 99"), ("0s:fail 123456789 2", "no module 123456789"),
    ("99999999s:jam 2 0", "after the end of the run"),
])
def test_faults_are_checked_against_the_structure(text: str, words: str) -> None:
    with pytest.raises(ChangeError, match=words):
        validate(parse_all([text]), load_config("eight7"), 30)


@settings(max_examples=60, deadline=None)
@given(st.text(alphabet="0123456789 :sjamfilx.-,at", max_size=30))
def test_fuzzed_fault_texts_parse_or_are_refused(text: str) -> None:
    try:
        changes = parse_all([text])
    except ChangeError as error:
        assert "\n" not in str(error)
        return
    try:
        validate(changes, load_config("eight7"), 30)
    except ChangeError as error:
        assert "\n" not in str(error)


def test_a_jammed_latch_never_moves_and_a_failing_one_once() -> None:
    s = load_config("eight7")
    s.jammed = frozenset({(2, 0)})
    change = s.unlatch(2, 0)
    assert not change.ok and change.cause == "jammed" and "does not open" in change.reason
    assert not s.unlatch(2, 0).ok  # for good
    s.jammed = frozenset()
    assert s.unlatch(2, 0).ok
    s.failing = frozenset({(2, 0)})
    copy = s.copy()
    change = s.latch(2, 0)
    assert not change.ok and change.cause == "jammed" and "(once)" in change.reason
    assert s.latch(2, 0).ok  # the next try closes
    assert copy.failing == frozenset({(2, 0)})  # a copy keeps its own faults


@pytest.mark.parametrize("fault, failed", [
    ("0s:jam 2 0", "disconnect_failed"),  # the first step: nothing to undo
    ("0s:jam 4 6", "disconnect_failed"),  # the second: the first is undone
    ("0s:fail 2 0", "connect_failed"),  # the last, a latch that does not close: both undone
])
@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 3)])
def test_rollback_ends_in_the_start_shape(fault: str, failed: str, loss: float, seed: int) -> None:
    report, _ = run(RELATCH, [fault], loss=loss, seed=seed)
    assert failed in [e["kind"] for e in report["events"]]
    assert shape(report) == structure_shape(load_config("eight7"))
    assert {m["final_state"]["relatch"] for m in report["modules"]} == {6}  # 2n: rolled back


def test_without_a_fault_the_relatch_ends_in_the_target_shape() -> None:
    report, trace = run(RELATCH, [])
    assert shape(report) == structure_shape(trace.final)
    assert shape(report) != structure_shape(load_config("eight7"))


def test_the_command_line_takes_faults_and_refuses_bad_ones() -> None:
    program = str(HERE / "relatch.rdcd")
    done = rdcd("simulate", program, *LATTICE, "--change", "0s:fail 2 0")
    assert done.returncode == 0 and "sequence relatch: rolled back" in done.stdout, done.stderr
    for bad, words in (("0s:jam 77 0", "no module 77"), ("0s:jam 2 9", "connector 0..7"),
                       ("0s:fail 2", "connector 0..7"), ("1e99s:jam 2 0", "TIME")):
        assert_clean_failure(rdcd("simulate", program, *LATTICE, "--change", bad), 2, words)


def test_an_undo_that_needs_a_jammed_latch_stays_in_between_and_says_so() -> None:
    # jammed after the first unlatch: the latch fails, the second unlatch is undone, and the undo
    # of the first would latch the jammed connector again: it is tried until the run ends
    done = rdcd("simulate", str(HERE / "relatch.rdcd"), *LATTICE, "--change", "3s:jam 2 0")
    assert done.returncode == 0 and "sequence relatch: rolling back (1 to undo)" in done.stdout, done.stderr


@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 3)])
def test_a_rollback_goes_on_past_a_wait(loss: float, seed: int) -> None:
    # a waitUntil step has nothing to undo: rolling back, the progress goes on past it (it once
    # stopped there for good, "rolling back (2 to undo)")
    text = RELATCH.replace("  LowerRight.disconnect(6);", "  LowerRight.waitUntil(1 == 1);")
    assert "waitUntil" in text
    report, _ = run(text, ["0s:fail 2 0"], loss=loss, seed=seed)
    assert "connect_failed" in [e["kind"] for e in report["events"]]
    assert shape(report) == structure_shape(load_config("eight7"))
    assert {m["final_state"]["relatch"] for m in report["modules"]} == {6}  # 2n: rolled back
