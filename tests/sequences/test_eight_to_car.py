"""The eight (eight7) into the shape of car7 with USSR's EightToCarSimulationJ as a skeleton: the
guided search (vm/lattice/plan.py ``guided``) keeps its eleven quarter turns (actors and signs),
the plan reaches car7's shape resting on its wheels, runs backwards to the eight in the model (same
cells, same connections), and the checker agrees forwards (tests/sequences/eight_to_car_steps.rdcd).
With a role per module it does not fit a module's ten program slots; examples/eight_to_car.rdcd,
one role with keys, compiles to tables and fits (docs/reconfiguration.md "The compact form"), and
then drives as a car (tests/sequences/test_eight_to_car_drives.py)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from vm.lattice.plan import Goal, guided, prune, replay

ROOT = Path(__file__).resolve().parents[2]
TEXT = (Path(__file__).resolve().parent / "eight_to_car_steps.rdcd").read_text()
ACTORS = [3, 4, 1, 4, 6, 0, 1, 0, 1, 3, 1]
SIGNS = [-1, -1, -1, 1, 1, -1, 1, 1, 1, 1, 1]


def shape(s) -> tuple[dict, set]:  # noqa: ANN001 - a Structure
    return ({m: (x.position, x.axis) for m, x in s.modules.items()},
            {(k.a, k.a_physical, k.b, k.b_physical) for k in s.links()})


@pytest.fixture(scope="module")
def found():  # noqa: ANN201 - the pruned ops
    start = load_config("eight7")
    result = guided(start, load_config("car7"), ACTORS, skeleton_signs=SIGNS)
    assert result.ok, result.reason
    return prune(start, result.ops, load_config("car7"))


def test_the_skeletons_turns_are_kept_and_the_car_is_reached(found) -> None:  # noqa: ANN001
    turns = [(op.module, op.arg) for op in found if op.kind == "rotate"]
    assert turns == list(zip(ACTORS, SIGNS, strict=True))
    assert len(found) == 23
    end = replay(load_config("eight7"), found)
    assert Goal(load_config("car7")).reached(end)
    wheels = sorted(m for m, x in end.modules.items() if x.position[2] == end.ground_z)
    assert wheels == [2, 3, 4, 5]  # resting on its wheels; axles 1 and 6, driver 0 on top
    assert end.modules[0].position[2] == end.ground_z + 2


def test_run_backwards_the_eight_comes_back_same_cells_same_connections(found) -> None:  # noqa: ANN001
    end = replay(load_config("eight7"), found)
    back = replay(end, [op.inverse() for op in reversed(found)])
    assert shape(back) == shape(load_config("eight7"))


def test_the_checker_runs_the_sequence_to_the_car() -> None:
    result = check_text(TEXT)
    # of the sequence none: E805 (27 fragments, test below) and fragments over 43 bytes only
    assert {d.code for d in result.diagnostics} <= {"W601", "E805"}
    final = result.traces[0].final
    assert Goal(load_config("car7")).reached(final)

def test_backwards_roles_by_the_eights_cells_name_the_same_modules() -> None:
    # Run backwards on the robot as the forward run leaves it, every module keeps the coordinates
    # it learned in the eight, so the roles (the eight's cells) name the same modules both ways
    # and the checker takes the car back to the eight. Started afresh in the car (the modules
    # learning the car's coordinates) only modules 0, 1 and 6 would hold a role: E810.
    from rdcd_core.sequences.check import backwards
    from rdcd_core.sequences.check import run as check_run

    result = check_text(TEXT)
    trace = backwards(result.model, result.program.sequences[0], result.traces[0])
    assert trace.diagnostics == []
    assert shape(trace.final) == shape(load_config("eight7"))
    afresh = check_run(result.model, result.program.sequences[0], result.traces[0].final, reverse=True)
    assert [d.code for d in afresh.diagnostics] == ["E810"]
    assert "no module holds M5" in afresh.diagnostics[0].message


def test_a_role_per_module_does_not_fit_ten_program_slots() -> None:
    # 23 steps by seven roles: 27 fragments in the ordinary form; the compact form (a table a
    # role) does not help seven roles either, so the program stays as it was, with E805
    result = check_text(TEXT)
    program = compile_model(result.model, text=TEXT)
    assert len(program.fragments) == 27 and "E805" in {d.code for d in program.diagnostics}


EXAMPLE = (ROOT / "examples" / "eight_to_car.rdcd").read_text()


def _cells(report: dict) -> tuple[dict, set]:
    return ({m["id"]: tuple(m["final_lattice"]) for m in report["modules"]},
            {tuple(c) for c in report["connections"]})


def test_the_example_one_role_by_keys_fits_as_tables() -> None:
    # examples/eight_to_car.rdcd: the same 23 steps (the last quarter turn the other way, which
    # reaches car7's cells and links too), one role, each module named by a key on the
    # coordinates it learned in the eight: the compact form (tables and one ACT behaviour, 4
    # fragments, 126 bytes), then the car's roles (no relay: the checker's model shows no module
    # plays them while the sequence runs): 10 fragments in all (27 with a role per module)
    result = check_text(EXAMPLE)
    assert result.diagnostics == []
    assert Goal(load_config("car7")).reached(result.traces[0].final)
    assert result.traces[0].played == {"Piece"}
    program = compile_model(result.model, text=EXAMPLE)
    assert not program.has_errors and len(program.fragments) == 10
    assert sum(len(f.code) for f in program.fragments) == 351
    assert all(len(f.code) <= 43 for f in program.fragments)
    assert any(b == 80 for f in program.fragments for b in f.code)  # TABLE
    assert sum(f.code.count(95) for f in program.fragments if f.name.startswith("Piece")) >= 1  # ACT
    relays = [f.name for f in program.fragments if b"eightToCar" in f.name.encode()]
    assert relays == []


@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 1), (0.2, 2)])
def test_the_lattice_world_ends_in_the_car_the_checker_finds(loss: float, seed: int) -> None:
    from sim.run import Options, simulate

    result = check_text(EXAMPLE)
    program = compile_model(result.model, text=EXAMPLE)
    options = Options(world="lattice", config="eight7", obstacle="none", duration=90, seed=seed,
                      packet_loss=loss)
    report = simulate(program, load_config("eight7"), options)
    assert _cells(report) == shape_of(result.traces[0].final)


def shape_of(structure) -> tuple[dict, set]:  # noqa: ANN001 - a Structure
    return ({m: tuple(x.position) for m, x in structure.modules.items()},
            {(k.a, k.a_physical, k.b, k.b_physical) for k in structure.links()})


def test_backwards_the_keys_learned_in_the_eight_give_the_eight_back() -> None:
    # the keys (2x + y) are the coordinates learned in the eight, which every module keeps in the
    # car: the checker runs the undo from the car to the eight, and the compiled undo is the same
    # tables read backwards
    from rdcd_core.sequences.check import backwards

    result = check_text(EXAMPLE)
    trace = backwards(result.model, result.program.sequences[0], result.traces[0])
    assert trace.diagnostics == []
    assert shape_of(trace.final) == shape_of(load_config("eight7"))
    program = compile_model(result.model, text=EXAMPLE, reverse="eightToCar")
    assert not program.has_errors and len(program.fragments) == 10


@pytest.mark.parametrize("loss, seed", [(0.0, 0), (0.2, 3)])
def test_the_lattice_world_runs_it_backwards_from_the_car_to_the_eight(loss: float, seed: int) -> None:
    from rdcd_core.sequences.roles import vm_frames
    from sim.run import Options, simulate

    result = check_text(EXAMPLE)
    forward = result.traces[0]
    program = compile_model(result.model, text=EXAMPLE, reverse="eightToCar")
    options = Options(world="lattice", config="eight7", obstacle="none", duration=90, seed=seed,
                      packet_loss=loss, frames=vm_frames(forward.learned))
    report = simulate(program, forward.final.copy(), options)
    assert _cells(report) == shape_of(load_config("eight7"))


def test_the_strict_skeleton_without_its_signs_is_bounded_and_says_how_close() -> None:
    result = guided(load_config("eight7"), load_config("car7"), ACTORS[:3], max_states=50)
    assert not result.ok and "lattice steps away" in result.reason


@pytest.mark.parametrize("start, actors, signs", [
    ("not a structure", ACTORS, SIGNS), (None, [9], []), (None, ACTORS, [1, -1])])
def test_bad_input_is_a_reason_never_an_exception(start, actors, signs) -> None:  # noqa: ANN001
    result = guided(load_config("eight7") if start is None else start, load_config("car7"),
                    actors, skeleton_signs=signs)
    assert not result.ok and result.reason


def test_a_bad_target_is_a_reason() -> None:
    result = guided(load_config("eight7"), "car7", ACTORS)
    assert not result.ok and "target" in result.reason


def _tool():  # noqa: ANN202 - the script's module
    spec = importlib.util.spec_from_file_location("plan_sequence", ROOT / "tools" / "plan_sequence.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_script_follows_a_guide(capsys: pytest.CaptureFixture[str]) -> None:
    tool = _tool()
    assert tool.main(["eight7", "car7", "--guide", ",".join(map(str, ACTORS)),
                      "--guide-signs=" + ",".join(map(str, SIGNS)), "--name", "eightToCar"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("// 23 steps") and "sequence eightToCar(eight7)" in out
    for bad in (["eight7", "car7", "--guide", "a,b"], ["eight7", "--chain", "--guide", "1"],
                ["eight7", "car7", "--guide", "1", "--guide-signs", "2"]):
        with pytest.raises(SystemExit) as stop:
            tool.main(bad)
        assert stop.value.code == 2
    assert tool.main(["eight7", "car7", "--guide", "3", "--max-states", "5"]) == 1


def test_the_command_line_runs_it_backwards_to_the_eight(tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from rdcd_core.cli import main

    out = tmp_path / "back.json"
    assert main(["simulate", str(ROOT / "examples" / "eight_to_car.rdcd"), "--config", "eight7",
                 "--world", "lattice", "--obstacle", "none", "--duration", "60",
                 "--reverse-sequence", "eightToCar", "--report", str(out)]) == 0
    assert "sequence eightToCar backwards: done" in capsys.readouterr().out
    report = json.loads(out.read_text())
    assert _cells(report) == shape_of(load_config("eight7"))
    # the progress ends at 23 backwards too, so the driver takes Go in the eight; no module there
    # has the axle's three connections, so no Axle and no wheel: nothing of the car acts
    roles = {m["id"]: m["final_role"] for m in report["modules"]}
    assert not {"Axle", "LeftWheel", "RightWheel"} & {str(r).split("@")[0] for r in roles.values()}
    assert "Go@Piece" in roles.values()


def test_a_module_refuses_a_frame_that_is_not_one() -> None:
    from rdcd_core.sequences.roles import vm_frames
    from sim.run import Options, simulate

    result = check_text(EXAMPLE)
    program = compile_model(result.model, text=EXAMPLE, reverse="eightToCar")
    frames = vm_frames(result.traces[0].learned)
    frames[3] = ((0, 0, 0), 1, tuple(range(8)))  # the origin is a NORTH_SOUTH place
    options = Options(world="lattice", config="eight7", obstacle="none", duration=1, frames=frames)
    with pytest.raises(ValueError, match="module 3: not a frame"):
        simulate(program, result.traces[0].final.copy(), options)


def test_a_round_of_discovery_begun_before_the_role_s_program_arrived_keeps_the_role() -> None:
    # seed 40 at 20 % loss: module 2 starts a round on the car roles' discovery programs (the only
    # ones kept then); Piece's program arrives during it and gives the role; the round, which
    # never ran Piece's program, used to end with "no role holds", drop Piece, and the act
    # behaviours arriving next skipped their install (HAS_ROLE Piece false): the sequence stopped
    from sim.run import Options, simulate

    result = check_text(EXAMPLE)
    program = compile_model(result.model, text=EXAMPLE)
    options = Options(world="lattice", config="eight7", obstacle="none", duration=90, seed=40,
                      packet_loss=0.2)
    report = simulate(program, load_config("eight7"), options)
    assert _cells(report) == shape_of(result.traces[0].final)
    done = max(e["t"] for e in report["events"] if e["kind"] in ("connect", "disconnect", "rotation_end"))
    during = {m["id"]: [role for t, role in m["role_history"] if t <= done] for m in report["modules"]}
    assert all(roles == ["Piece"] for roles in during.values()), during
