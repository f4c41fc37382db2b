"""The lattice planner (vm/lattice/plan.py) and its script (tools/plan_sequence.py): it finds a
known short sequence, says cleanly when none is found within its bounds, never raises on a bad
target, and every plan replays through the structure's own operations."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from sim.config import load_config
from vm.lattice.plan import FlatChain, Goal, Op, canonical, macros, plan, replay
from vm.lattice.structure import ModuleSpec, make_structure

ROOT = Path(__file__).resolve().parents[2]


def _tool():  # noqa: ANN202 - the script's module
    spec = importlib.util.spec_from_file_location("plan_sequence", ROOT / "tools" / "plan_sequence.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_finds_a_known_one_turn_sequence() -> None:
    start = load_config("random4-seed109")  # examples/move_one.rdcd's structure
    moved = [m for m in macros(start, keep_entry=True) if len(m) == 1]
    assert moved, "a turn that needs no unlatch"
    target = replay(start, moved[0])
    found = plan(start, target, max_states=50)
    assert found.ok and 1 <= len(found.ops) <= 3
    assert Goal(target).reached(replay(start, found.ops))


def test_the_target_up_to_a_quarter_turn_about_z_and_a_translation() -> None:
    car = load_config("car7")
    turned = make_structure([ModuleSpec(m, (-s.position[1] + 1, s.position[0] + 1, s.position[2] + 2),
                                        {1: 2, 2: 1, 3: 3}[s.axis]) for m, s in car.modules.items()],
                            entry=4)  # the wheel that lands on the origin, NORTH_SOUTH
    assert canonical(turned)[0] in {canonical(car, k)[0] for k in range(4)}
    assert plan(car, turned).ok and plan(car, turned).ops == []


def test_car_to_a_flat_chain_in_nine_steps() -> None:
    found = plan(load_config("car7"), FlatChain(7, reversible=False), max_states=300,
                 keep_entry=False, reversible=False)
    assert found.ok and len(found.ops) == 9
    final = replay(load_config("car7"), found.ops)
    assert FlatChain(7).reached(final) and len(final.parts()) == 1
    final.check_invariants()


def test_a_reversible_plan_never_opens_a_link_of_one_sex() -> None:
    car = load_config("car7")  # its axle-wheel links join two male connectors
    same = {(k.a, k.a_physical) for k in car.links() if (k.a_physical + k.b_physical) % 2 == 0}
    assert same and all(not (op[-1].kind == "unlatch" and (op[-1].module, op[-1].arg) in same)
                        for op in macros(car) for op in [op[:i + 1] for i in range(len(op))])


def test_the_reversible_car_to_chain_plan_undone_gives_car7_back_exactly() -> None:
    # found by tools/plan_sequence.py car7 --chain --move-entry --max-states 20000 (12344 states)
    ops = [Op("rotate", 1, 1), Op("latch", 3, 6), Op("unlatch", 0, 6), Op("rotate", 3, 1),
           Op("latch", 0, 6), Op("unlatch", 3, 6), Op("rotate", 5, -1), Op("latch", 5, 0),
           Op("latch", 6, 4), Op("unlatch", 0, 2), Op("rotate", 0, 1), Op("unlatch", 5, 0)]
    car = load_config("car7")
    chain = replay(car, ops)
    assert FlatChain(7).reached(chain)
    back = replay(chain, [op.inverse() for op in reversed(ops)])
    assert {m: s.position for m, s in back.modules.items()} == \
        {m: s.position for m, s in car.modules.items()}
    assert back.links() == car.links()
    # its eleventh step turns the driver's free hemisphere and carries nothing: without it the
    # same chain, and the same car back (examples/car_to_snake.rdcd)
    assert ops[10] == Op("rotate", 0, 1) and replay(car, ops[:10]).modules[0].position == \
        chain.modules[0].position
    short = ops[:10] + ops[11:]
    assert FlatChain(7).reached(replay(car, short))
    assert replay(replay(car, short), [op.inverse() for op in reversed(short)]).links() == car.links()


def test_no_sequence_within_the_bounds_is_a_clean_answer() -> None:
    found = plan(load_config("eight7"), load_config("car7"), max_states=3)
    assert not found.ok and found.reason == "no sequence found within 3 states (at most 30 steps)"
    found = plan(load_config("car7"), FlatChain(7, reversible=False), max_steps=2, keep_entry=False,
                 reversible=False)
    assert not found.ok and found.reason == "no sequence within 2 steps"


@pytest.mark.parametrize("target", [None, "car7", 42, object()])
def test_a_bad_target_is_a_reason_never_an_exception(target: object) -> None:
    found = plan(load_config("car7"), target)  # type: ignore[arg-type]
    assert not found.ok and found.reason.startswith("not a target structure")


def test_a_target_of_another_size_or_a_bad_start() -> None:
    assert plan(load_config("car7"), load_config("snake5")).reason == \
        "the target has 5 modules, the start 7"
    assert plan("car7", load_config("car7")).reason == "not a start structure"  # type: ignore[arg-type]


def test_replay_names_the_step_that_cannot_happen() -> None:
    found = plan(load_config("car7"), FlatChain(7, reversible=False), max_states=300,
                 keep_entry=False, reversible=False)
    with pytest.raises(ValueError, match="step 2"):
        replay(load_config("car7"), [found.ops[0], found.ops[0].inverse(), found.ops[0].inverse()]
               [:1] + [found.ops[2].inverse()])


def test_the_script_prints_a_sequence_and_exit_codes(capsys: pytest.CaptureFixture[str]) -> None:
    tool = _tool()
    assert tool.main(["car7", "--chain", "--move-entry", "--irreversible", "--name",
                      "carToSnake"]) == 0
    out = capsys.readouterr().out
    assert "sequence carToSnake(car7) {" in out and out.count("turnQuarters") == 3
    assert tool.main(["eight7", "car7", "--max-states", "2"]) == 1
    assert "no sequence found within 2 states" in capsys.readouterr().err
    assert tool.main(["no-such-config", "--chain"]) == 2
    assert tool.main(["car7", "snake5"]) == 1
    with pytest.raises(SystemExit):
        tool.main(["car7"])  # neither a target nor --chain
    with pytest.raises(SystemExit):
        tool.main(["car7", "--chain", "--max-states", "-1"])


def test_the_checker_reads_places_in_the_entry_module_s_frame() -> None:
    from rdcd_core.sequences.roles import entry_frame
    from vm.lattice.mount import IDENTITY

    car = load_config("car7")
    assert {m: s.position for m, s in entry_frame(car).items()} == \
        {m: s.position for m, s in car.modules.items()}
    moved = replay(car, [Op("rotate", 1, 1), Op("latch", 3, 6), Op("unlatch", 0, 6),
                         Op("rotate", 3, 1)])  # the last turn carries the entry module
    assert moved.modules[0].position != (0, 0, 0)
    seen = entry_frame(moved)
    assert seen[0].position == (0, 0, 0) and seen[0].axis == 2 and seen[0].mount == IDENTITY
    # distances between modules are what they are in the structure
    for m in moved.modules:
        d = [a - b for a, b in zip(moved.modules[m].position, moved.modules[0].position, strict=True)]
        assert sorted(map(abs, d)) == sorted(map(abs, seen[m].position))


def test_the_script_stopped_by_ctrl_c_says_so_in_one_line() -> None:
    import signal
    import subprocess
    import sys
    import time

    proc = subprocess.Popen([sys.executable, str(ROOT / "tools" / "plan_sequence.py"), "eight7", "car7",
                             "--max-states", "1000000"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, cwd=ROOT)
    time.sleep(8)  # the search has started (imports and the configuration take about a second)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert out == ""
    assert err.strip() == "plan_sequence: interrupted; no sequence printed"
