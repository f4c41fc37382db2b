"""Steps of a parallel block act at once and are counted in order (docs/reconfiguration.md
"Parallel blocks"): the progress is the number of steps done, relayed by max; step j of a block
acts as soon as the block has begun and counts k + j -> k + j + 1 in its turn. A model of that
protocol under any order of delivery and loss; the lattice runs; the limits said by the compiler
(E805)."""

from __future__ import annotations

import random
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from rdcd_core.sequences.progress import done_value, progress_plan, steps_done
from rdcd_core.sequences.roles import vm_frames
from rdcd_core.syntax import ast, parse
from sim.config import load_config
from sim.run import Options, simulate
from tests.sequences.programs import without_blocks
from tests.sequences.shapes import shape, structure_shape
from vm.lattice.outside import parse_all

HERE = Path(__file__).parent
EIGHT = (HERE.parents[1] / "examples" / "eight_to_snake.rdcd").read_text()
PARALLEL = (HERE / "eight_to_snake_parallel.rdcd").read_text()
TURNS = (HERE / "parallel_turns.rdcd").read_text()


def run(text: str, *, loss: float = 0.0, seed: int = 0, duration: float = 40.0,
        reverse: str | None = None, config: str = "eight7",
        changes: tuple[str, ...] = ()) -> tuple[dict, object]:
    result = check_text(text)
    assert not result.has_errors, result.diagnostics
    start = result.traces[0].final if reverse else load_config(config)
    program = compile_model(result.model, text=text, reverse=reverse)
    assert not program.has_errors and max(f.size for f in program.fragments) <= 43
    # backwards: the robot as the forward run leaves it, each module in the frame it learned
    frames = vm_frames(result.traces[0].learned) if reverse else {}
    options = Options(world="lattice", config=config, obstacle="none", duration=duration, seed=seed,
                      packet_loss=loss, frames=frames, outside_changes=parse_all(list(changes)))
    return simulate(program, start, options), result.traces[0]


# ----------------------------------------------------------------------------- the protocol


def protocol(edges: list[tuple[int, int]], n: int, actors: list[int], order: random.Random,
             loss: float) -> tuple[list[int], list[int]]:
    """Every module: value := max(value, a neighbour's last value heard); the actor of step j acts
    once when its value is in 0..j and counts j -> j + 1 when it has acted and its value is j —
    as the generated code does, one event at a time. The values, and how often each step acted."""
    value = [0] * n
    acted = [0] * len(actors)
    heard = {(a, b): 0 for a, b in edges} | {(b, a): 0 for a, b in edges}
    for _ in range(40000):
        if all(v == len(actors) for v in value):
            break
        kind = order.random()
        if kind < 0.4:  # a published value travels (or is lost: sent again later)
            a, b = order.choice(list(heard))
            if order.random() >= loss:
                heard[(a, b)] = value[a]
        elif kind < 0.7:  # a relay run
            m = order.randrange(n)
            value[m] = max([value[m]] + [v for (a, b), v in heard.items() if b == m])
        else:  # a step's behaviours: act once from the block's start, count in its turn
            j = order.randrange(len(actors))
            m = actors[j]
            if value[m] <= j and not acted[j]:
                acted[j] += 1
            if value[m] == j and acted[j]:
                value[m] = j + 1
    return value, acted


@settings(max_examples=80, deadline=None)
@given(st.integers(2, 9), st.integers(1, 4), st.integers(0, 10**6), st.sampled_from([0.0, 0.3, 0.6]))
def test_a_block_relayed_by_max_counts_every_step_once(n: int, m: int, seed: int, loss: float) -> None:
    order = random.Random(seed)
    edges = [(k, order.randrange(k)) for k in range(1, n)]  # a random tree: connected
    edges += [(order.randrange(n), order.randrange(n)) for _ in range(order.randrange(3))]
    edges = [(a, b) for a, b in edges if a != b]
    actors = order.sample(range(n), min(m, n))  # one step a module (E816)
    value, acted = protocol(edges, n, actors, order, loss)
    assert value == [len(actors)] * n
    assert acted == [1] * len(actors)  # every step acted, once


@given(st.lists(st.integers(1, 5), min_size=1, max_size=6), st.booleans())
def test_progress_values_count_the_steps_done(sizes: list[int], rollback: bool) -> None:
    items = " ".join("A.waitUntil(1 == 1);" if k == 1 else
                     "parallel { " + "A.waitUntil(1 == 1); " * k + "}" for k in sizes)
    sequence = parse(f"sequence s {'rollback ' if rollback else ''}{{ {items} }}").program.sequences[0]
    plan = progress_plan(sequence)
    assert sum(len(s.steps) for s in plan) == sum(sizes)
    assert done_value(sequence) == sum(sizes)  # a block's steps count one each
    assert steps_done(sequence, done_value(sequence)) == sum(sizes)
    assert steps_done(sequence, 0) == 0
    for a, b in zip(plan, plan[1:], strict=False):
        assert b.base == a.base + a.width and a.width == len(a.steps)
    if rollback:  # one after the other: the undo counts steps
        assert all(s.width == 1 and s.block == 0 for s in plan)


# ----------------------------------------------------------------------------- the lattice runs


def test_the_two_disconnects_of_the_eight_run_at_once() -> None:
    result = check_text(PARALLEL)
    assert not result.diagnostics, result.diagnostics
    report, trace = run(PARALLEL)
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["eightToSnake"] for m in report["modules"]} == {2}  # both counted
    assert shape(report) == shape(run(EIGHT)[0])  # the same snake as one after the other


@pytest.mark.parametrize("loss, seed", [(0.2, 1), (0.3, 2), (0.3, 3)])
def test_lost_packets_never_lose_a_step(loss: float, seed: int) -> None:
    report, trace = run(PARALLEL, loss=loss, seed=seed, duration=60)
    assert report["messages"]["dropped"] > 0
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["eightToSnake"] for m in report["modules"]} == {2}


def test_run_backwards_the_block_gives_the_eight_back() -> None:
    report, _ = run(PARALLEL, reverse="eightToSnake", loss=0.1, seed=4, duration=60)
    assert shape(report) == structure_shape(load_config("eight7"))


def test_turns_of_a_block_overlap_in_time() -> None:
    report, trace = run(TURNS)
    assert shape(report) == structure_shape(trace.final)
    turns = {e["module"]: e["t"] for e in report["events"] if e["kind"] == "rotation_start"}
    ends = {e["module"]: e["t"] for e in report["events"] if e["kind"] == "rotation_end"}
    assert set(turns) == {2, 4} and max(turns.values()) < min(ends.values())  # both turning at once
    sequential = TURNS.replace("parallel {", "").replace("  }\n}", "}")
    report, _ = run(sequential)
    turns = {e["module"]: e["t"] for e in report["events"] if e["kind"] == "rotation_start"}
    ends = {e["module"]: e["t"] for e in report["events"] if e["kind"] == "rotation_end"}
    assert max(turns.values()) >= min(ends.values())  # one after the other


def test_the_summary_counts_the_steps_of_a_block(tmp_path: Path) -> None:
    import subprocess
    import sys

    program = HERE / "eight_to_snake_parallel.rdcd"
    common = [sys.executable, "-m", "rdcd_core", "simulate", str(program), "--config", "eight7",
              "--world", "lattice", "--obstacle", "none", "--duration", "8"]
    done = subprocess.run(common, capture_output=True, text=True, timeout=300)
    assert "sequence eightToSnake: done" in done.stdout, done.stdout + done.stderr
    lost = subprocess.run([*common, "--packet-loss", "1"], capture_output=True, text=True, timeout=300)
    assert "sequence eightToSnake: not done: 0 of 2 steps" in lost.stdout


# ----------------------------------------------------------------------------- blocks in tables

EIGHT_TO_CAR = (HERE / "eight_to_car_parallel.rdcd").read_text()
CAR_TO_SNAKE = (HERE / "car_to_snake_parallel.rdcd").read_text()


def turning(report: dict) -> list[tuple[float, float]]:
    starts = sorted((e["t"], e["module"]) for e in report["events"] if e["kind"] == "rotation_start")
    ends = sorted((e["t"], e["module"]) for e in report["events"] if e["kind"] == "rotation_end")
    return [(t, next(u for u, n in ends if n == m and u >= t)) for t, m in starts]


def test_blocks_of_two_take_tables_with_a_lane() -> None:
    result = check_text(EIGHT_TO_CAR)
    assert not result.diagnostics, result.diagnostics
    program = compile_model(result.model, text=EIGHT_TO_CAR)
    assert not program.diagnostics and len(program.fragments) <= 10
    assert max(f.size for f in program.fragments) <= 43
    assert {"eightToCar_t", "eightToCar_a", "eightToCar_par"} <= {s.name for s in program.states}
    # in the ordinary form each step would take a behaviour of its own (E121)
    from rdcd_core.sequences.lower import lowered_model

    assert "E121" in {d.code for d in lowered_model(result.model).diagnostics}


def test_blocks_in_tables_turn_at_once_and_end_sooner() -> None:
    report, trace = run(EIGHT_TO_CAR, duration=40)
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["eightToCar"] for m in report["modules"]} == {23}  # the steps counted
    spans = turning(report)
    assert any(a[0] < b[0] < a[1] for a, b in zip(spans, spans[1:], strict=False))  # two turning at once
    alone, _ = run(without_blocks(EIGHT_TO_CAR), duration=40)
    assert not any(a[0] < b[0] < a[1] for a, b in zip(turning(alone), turning(alone)[1:], strict=False))
    assert shape(alone) == shape(report)
    assert done_at(report, "eightToCar", 23) < done_at(alone, "eightToCar", 23) - 2.0  # two turns saved


def done_at(report: dict, name: str, value: int) -> float:
    return min(t for m in report["modules"] for t, state, v in m["state_history"]
               if state == name and v == value)


@pytest.mark.parametrize("loss, seed", [(0.2, 5), (0.3, 6)])
def test_blocks_in_tables_under_loss_and_backwards(loss: float, seed: int) -> None:
    report, trace = run(EIGHT_TO_CAR, loss=loss, seed=seed, duration=90)
    assert report["messages"]["dropped"] > 0
    assert shape(report) == structure_shape(trace.final)
    back, _ = run(EIGHT_TO_CAR, loss=loss, seed=seed, duration=90, reverse="eightToCar")
    assert shape(back) == structure_shape(load_config("eight7"))


def test_a_block_step_whose_latch_fails_once_is_tried_again_and_counted_once() -> None:
    # module 6 (key 8) latches its connector 6 in the block 16+17, the first time it latches it:
    # that latch fails once, and the step is done again from the lane or the table
    report, trace = run(EIGHT_TO_CAR, duration=60, changes=("0s:fail 6 6",))
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["eightToCar"] for m in report["modules"]} == {23}
    mine = [(e["kind"], e["detail"].get("connector")) for e in report["events"] if e["module"] == 6]
    assert mine.count(("connect_failed", 6)) == 1 and mine.count(("connect", 6)) == 1  # once, then done


def test_car_to_snake_with_blocks_reaches_the_snake_and_gives_the_car_back() -> None:
    program = compile_model(check_text(CAR_TO_SNAKE).model, text=CAR_TO_SNAKE)
    assert not program.diagnostics and len(program.fragments) <= 10  # the crawl fits too
    report, trace = run(CAR_TO_SNAKE, config="car7", loss=0.1, seed=2, duration=60)
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["carToSnake"] for m in report["modules"]} == {12}
    back, _ = run(CAR_TO_SNAKE, config="car7", duration=60, reverse="carToSnake")
    assert shape(back) == structure_shape(load_config("car7"))


def test_a_block_of_three_keeps_the_ordinary_form() -> None:
    from rdcd_core.sequences.compact import ahead_steps, applies

    def sequence(text: str) -> ast.Sequence:
        return parse(text).program.sequences[0]

    three = sequence("sequence s { parallel { A.connect(0); B.connect(0); C.connect(0); } }")
    two = sequence("sequence s { A.connect(0); parallel { B.connect(0); C.connect(0); } }")
    assert not applies(three) and applies(two)
    assert ahead_steps(two) == {2: 1} and ahead_steps(two, reverse=True) == {1: 0}
    rollback = sequence("sequence s rollback { parallel { B.connect(0); C.connect(0); } }")
    assert applies(rollback) and ahead_steps(rollback) == {}  # one after the other


# ----------------------------------------------------------------------------- the limits


def block(k: int) -> str:
    return "parallel { " + " ".join(f"Hub(self.x() == {i}).waitUntil(1 == 1);" for i in range(k)) + " }"


def codes(text: str) -> list[str]:
    return [d.code for d in check_text(text).diagnostics]


def with_sequence(body: str) -> str:
    old = "sequence eightToSnake(eight7) {\n  UpperLeft.disconnect(0);\n  LowerRight.disconnect(6);\n}"
    return EIGHT.replace(old, f"sequence s {{\n{body}\n}}")


@pytest.mark.parametrize("text", [with_sequence("  " + block(8)), with_sequence("  " + block(60)),
                                  with_sequence(("  " + block(7) + "\n") * 9)])
def test_huge_blocks_are_refused_with_a_diagnostic(text: str) -> None:
    found = codes(text)
    assert found and "E100" not in found and ("E805" in found or "E803" in found or "E121" in found)


def test_a_block_of_seven_fits_the_progress_byte() -> None:
    # once 2^7 - 1 values (E806); now seven values
    result = check_text(with_sequence("  UpperLeft.waitUntil(1 == 1);\n  " + block(7)))
    assert "E806" not in [d.code for d in result.diagnostics]
    sequence = result.model.program.sequences[0]
    assert done_value(sequence) == 8


def test_too_many_fragments_are_refused_at_a_step() -> None:
    # the same sequence with Hub, Side and two more roles as four roles: 11 fragments (nine with one
    # role, as shipped)
    text = TURNS.replace("role Rest {\n  self.center_position == NORTH_SOUTH || self.x() - self.y() == 2;\n}",
                         "role Hub { self.center_position == NORTH_SOUTH; }\n"
                         "role Side { self.x() - self.y() == 2; }\n"
                         "role Far { self.x() == 9; }\nrole Near { self.x() == 8; }")
    text = text.replace("Rest }", "Hub, Side, Far, Near }")
    assert text != TURNS
    result = check_text(text)
    (d,) = [d for d in result.diagnostics if d.code == "E805"]
    assert "11 fragments" in d.message and "10 program slots" in d.message
    assert text[d.span.start:].startswith("LowerRight.turnQuarters(2);")
    assert "E805" not in codes(TURNS)


# ----------------------------------------------------------------------------- fuzzed blocks

STEPS = st.sampled_from(["UpperLeft.disconnect(0);", "LowerRight.disconnect(6);", "UpperLeft.connect(0);",
                         "UpperLeft.turnQuarters(2);", "LowerRight.turnQuarters(-1);",
                         "Hub(self.x() == 2).waitUntil(1 == 1);", "Side(self.x() == 1).connect(2);",
                         "Nobody.connect(0);", "UpperLeft.connect(1);"])
BLOCKS = st.lists(st.one_of(STEPS, st.lists(STEPS, max_size=9).map(
    lambda s: "parallel { " + " ".join(s) + " }")), max_size=6)


@settings(max_examples=50, deadline=None)
@given(BLOCKS, st.sampled_from(["(eight7)", "", "(car7)"]), st.booleans())
def test_fuzzed_blocks_fit_the_vm_or_say_why(items: list[str], config: str, rollback: bool) -> None:
    body = "\n".join(f"  {item}" for item in items)
    header = f"sequence s{config}{' rollback' if rollback else ''} {{"
    text = with_sequence(body).replace("sequence s {", header)
    result = check_text(text)
    assert all(d.code != "E100" and 0 <= d.span.start <= d.span.end <= len(text) for d in result.diagnostics)
    if result.has_errors:
        return
    for reverse in (None, "s"):
        program = compile_model(result.model, text=text, reverse=reverse)
        assert all(d.code != "E100" for d in program.diagnostics)
        if not program.has_errors:  # what compiles fits the VM: ten slots, a slot's bytes
            assert len(program.fragments) <= 10
            assert all(f.size <= 64 for f in program.fragments)
