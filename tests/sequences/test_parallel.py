"""Steps of a parallel block run at once (docs/reconfiguration.md "How it runs"): the progress of a
block is a bitmask of its steps done, relayed by max, each missing bit added again by its step's
module. A model of that protocol under any order of delivery and loss; the lattice runs; the
limits said by the compiler (E805, E806)."""

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
from rdcd_core.syntax import parse
from sim.config import load_config
from sim.run import Options, simulate
from tests.sequences.shapes import shape, structure_shape

HERE = Path(__file__).parent
EIGHT = (HERE.parents[1] / "examples" / "eight_to_snake.rdcd").read_text()
PARALLEL = (HERE / "eight_to_snake_parallel.rdcd").read_text()
TURNS = (HERE / "parallel_turns.rdcd").read_text()


def run(text: str, *, loss: float = 0.0, seed: int = 0, duration: float = 40.0,
        reverse: str | None = None) -> tuple[dict, object]:
    result = check_text(text)
    assert not result.has_errors, result.diagnostics
    start = result.traces[0].final if reverse else load_config("eight7")
    program = compile_model(result.model, text=text, reverse=reverse)
    assert not program.has_errors and max(f.size for f in program.fragments) <= 43
    # backwards: the robot as the forward run leaves it, each module in the frame it learned
    frames = vm_frames(result.traces[0].learned) if reverse else {}
    options = Options(world="lattice", config="eight7", obstacle="none", duration=duration, seed=seed,
                      packet_loss=loss, frames=frames)
    return simulate(program, start, options), result.traces[0]


# ----------------------------------------------------------------------------- the protocol


def protocol(edges: list[tuple[int, int]], n: int, actors: list[int], order: random.Random,
             loss: float) -> list[int]:
    """Every module: value := max(value, a neighbour's last value heard); actor j (acted already)
    adds bit 2^j while its bit is missing — as the generated code does, one event at a time."""
    value = [0] * n
    heard = {(a, b): 0 for a, b in edges} | {(b, a): 0 for a, b in edges}
    for _ in range(20000):
        if all(v == (1 << len(actors)) - 1 for v in value):
            break
        kind = order.random()
        if kind < 0.4:  # a published value travels (or is lost: sent again later)
            a, b = order.choice(list(heard))
            if order.random() >= loss:
                heard[(a, b)] = value[a]
        elif kind < 0.8:  # a relay run
            m = order.randrange(n)
            value[m] = max([value[m]] + [v for (a, b), v in heard.items() if b == m])
        else:  # a step's mark run
            j = order.randrange(len(actors))
            m = actors[j]
            if not value[m] >> j & 1:
                value[m] += 1 << j
    return value


@settings(max_examples=80, deadline=None)
@given(st.integers(2, 9), st.integers(1, 4), st.integers(0, 10**6), st.sampled_from([0.0, 0.3, 0.6]))
def test_the_bitmask_relayed_by_max_ends_with_every_bit(n: int, m: int, seed: int, loss: float) -> None:
    order = random.Random(seed)
    edges = [(k, order.randrange(k)) for k in range(1, n)]  # a random tree: connected
    edges += [(order.randrange(n), order.randrange(n)) for _ in range(order.randrange(3))]
    edges = [(a, b) for a, b in edges if a != b]
    actors = [order.randrange(n) for _ in range(m)]
    value = protocol(edges, n, actors, order, loss)
    assert value == [(1 << m) - 1] * n


@given(st.lists(st.integers(1, 5), min_size=1, max_size=6), st.booleans())
def test_progress_values_count_the_steps_done(sizes: list[int], rollback: bool) -> None:
    items = " ".join("A.waitUntil(1 == 1);" if k == 1 else
                     "parallel { " + "A.waitUntil(1 == 1); " * k + "}" for k in sizes)
    sequence = parse(f"sequence s {'rollback ' if rollback else ''}{{ {items} }}").program.sequences[0]
    plan = progress_plan(sequence)
    assert sum(len(s.steps) for s in plan) == sum(sizes)
    assert steps_done(sequence, done_value(sequence)) == sum(sizes)
    assert steps_done(sequence, 0) == 0
    for a, b in zip(plan, plan[1:], strict=False):
        assert b.base == a.base + a.width
    if rollback:  # one after the other: the undo counts steps
        assert all(s.width == 1 and s.block == 0 for s in plan)
        assert done_value(sequence) == sum(sizes)


# ----------------------------------------------------------------------------- the lattice runs


def test_the_two_disconnects_of_the_eight_run_at_once() -> None:
    result = check_text(PARALLEL)
    assert not result.diagnostics, result.diagnostics
    report, trace = run(PARALLEL)
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["eightToSnake"] for m in report["modules"]} == {3}  # both bits
    assert shape(report) == shape(run(EIGHT)[0])  # the same snake as one after the other


@pytest.mark.parametrize("loss, seed", [(0.2, 1), (0.3, 2), (0.3, 3)])
def test_lost_packets_never_lose_a_bit(loss: float, seed: int) -> None:
    report, trace = run(PARALLEL, loss=loss, seed=seed, duration=60)
    assert report["messages"]["dropped"] > 0
    assert shape(report) == structure_shape(trace.final)
    assert {m["final_state"]["eightToSnake"] for m in report["modules"]} == {3}


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


# ----------------------------------------------------------------------------- the limits


def block(k: int) -> str:
    return "parallel { " + " ".join(f"Hub(self.x() == {i}).waitUntil(1 == 1);" for i in range(k)) + " }"


def codes(text: str) -> list[str]:
    return [d.code for d in check_text(text).diagnostics]


def with_sequence(body: str) -> str:
    old = "sequence eightToSnake(eight7) {\n  UpperLeft.disconnect(0);\n  LowerRight.disconnect(6);\n}"
    return EIGHT.replace(old, f"sequence s {{\n{body}\n}}")


def test_a_block_past_a_state_byte_is_refused_at_its_line() -> None:
    text = with_sequence("  UpperLeft.waitUntil(1 == 1);\n  " + block(7))
    assert text != EIGHT
    result = check_text(text)
    (d,) = [d for d in result.diagnostics if d.code == "E806"]
    assert text[d.span.start:].startswith("parallel") and "signed byte" in d.message
    assert "E806" not in codes(with_sequence("  " + block(6)))


@pytest.mark.parametrize("text", [with_sequence("  " + block(8)), with_sequence("  " + block(60)),
                                  with_sequence(("  " + block(7) + "\n") * 9)])
def test_huge_blocks_are_refused_with_a_diagnostic(text: str) -> None:
    found = codes(text)
    assert found and "E100" not in found and ("E806" in found or "E803" in found)


def test_too_many_fragments_are_refused_at_a_step() -> None:
    # the same sequence with Hub and Side as two roles: 11 fragments (ten with one role, as shipped)
    text = TURNS.replace("role Rest {\n  self.center_position == NORTH_SOUTH || self.x() - self.y() == 2;\n}",
                         "role Hub { self.center_position == NORTH_SOUTH; }\n"
                         "role Side { self.x() - self.y() == 2; }").replace("Rest }", "Hub, Side }")
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
