"""Structures that change in the lattice world, driven as ``rdcd simulate`` drives it (``sim.run``):
a module moves by a neighbour's quarter turn and latches (examples/move_one.rdcd), a blocked turn
is an event the program can tell, outside changes, the report's structure fields."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.semantics import analyze
from rdcd_core.syntax import parse
from sim.config import load_config
from sim.run import Options, simulate
from vm.lattice.outside import parse_all

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def program_of(text: str):  # noqa: ANN201
    program = compile_model(analyze(parse(text).program), text=text)
    assert not program.has_errors, program.diagnostics
    return program


def run(text: str, config: str, duration: float, changes: tuple[str, ...] = (), **kw: object) -> dict:
    options = Options(world=str(kw.pop("world", "lattice")), config=config,
                      obstacle=str(kw.pop("obstacle", "none")),
                      duration=duration, outside_changes=parse_all(list(changes)), **kw)  # type: ignore[arg-type]
    return simulate(program_of(text), load_config(config), options)


def by_id(report: dict) -> dict[int, dict]:
    return {m["id"]: m for m in report["modules"]}


def kinds(report: dict) -> list[str]:
    return [e["kind"] for e in report["events"] if e["kind"] not in ("command", "program", "role", "links")]


def test_move_one_moves_a_module_and_latches_it_elsewhere() -> None:
    structure = load_config("random4-seed109")
    report = run((EXAMPLES / "move_one.rdcd").read_text(), "random4-seed109", 10)
    modules = by_id(report)
    assert modules[2]["lattice"] == [2, 1, 1] and modules[2]["final_lattice"] == [2, 0, 0]
    assert modules[2]["final_orientation"] == "NS"
    assert report["connections"] == [[0, 3, 1, 0], [0, 7, 3, 3], [2, 0, 3, 7]]
    assert kinds(report) == ["action", "rotation_start", "rotation_end", "action", "connect", "action",
                             "disconnect"]
    start = next(e for e in report["events"] if e["kind"] == "rotation_start")
    end = next(e for e in report["events"] if e["kind"] == "rotation_end")
    assert end["t"] - start["t"] == pytest.approx(1.5, abs=0.02)  # a quarter of the joint's 6 s turn
    assert start["detail"]["line"] == 17 and start["detail"]["carried"] == [2]
    assert "structure: 1 latched, 1 unlatched, 1 turn done" in _summary(report)
    assert load_config("random4-seed109").links() == structure.links()  # the run changed a copy


def _summary(report: dict) -> str:
    from sim.report import summary

    return summary(report)


BLOCKED = """
role Driver {
  self.x() == 0 && self.y() == 0 && self.z() == 0;
  startup go() {
    if (!self.turnQuarters(1)) { self.setLed(7); }
    if (!self.connect(0)) { self.setLed(5); }
    if (self.disconnect(4)) { self.setLed(1); }
  }
}
deployment { Driver }
"""


def test_impossible_actions_are_events_and_the_program_can_tell() -> None:
    report = run(BLOCKED, "car7", 5)
    failed = [e for e in report["events"] if e["kind"].endswith("_failed")]
    assert [e["kind"] for e in failed] == ["rotation_failed", "connect_failed", "disconnect_failed"]
    assert failed[0]["detail"]["cause"] in ("ground", "collision", "loop")
    assert all(e["detail"]["line"] for e in failed)
    assert by_id(report)[0]["errors"] == []
    links = load_config("car7").links()
    assert report["connections"] == [[k.a, k.a_physical, k.b, k.b_physical] for k in links]


def test_outside_changes_in_the_report() -> None:
    text = (EXAMPLES / "lose_a_wheel.rdcd").read_text()
    report = run(text, "car7", 30, ("20s:detach 3", "25s:stop 5", "26s:attach 9 at 2,0,-2"),
                 obstacle="wall:1.0")
    modules = by_id(report)
    assert modules[3]["final_lattice"] is None and modules[9]["lattice"] == [2, 0, -2]
    outside = [e for e in report["events"] if e["kind"] == "outside"]
    assert [(e["t"], e["module"]) for e in outside] == [(20.0, 3), (25.0, 5), (26.0, 9)]
    assert all(3 not in c[::2] for c in report["connections"])
    assert "3 outside changes" in _summary(report)


def test_a_detach_that_splits_reports_the_parts() -> None:
    report = run((EXAMPLES / "lose_a_wheel.rdcd").read_text(), "car7", 25, ("20s:detach 1",))
    assert report["parts"] == [[0, 2, 5, 6], [3], [4]]
    split = [e for e in report["events"] if e["kind"] == "split"]
    assert split and split[0]["detail"]["parts"] == [[0, 2, 5, 6], [3], [4]]


def fresh_roles(config: str, text: str, without: int) -> dict[int, str | None]:
    """The roles a fresh start gives the shape that is left (the entry's part)."""
    structure = load_config(config)
    structure.remove(without)
    from sim.run import Run

    program = program_of(text)
    r = Run(program, structure, Options(world="lattice", obstacle="none", duration=10))
    r.run_to_end()
    return {m: r.roles.name(rt.role) if rt.role else None for m, rt in r.runtimes.items()
            if m in structure.part_of(structure.entry)}


def test_lose_a_wheel_the_remaining_modules_take_the_roles_of_their_new_shape() -> None:
    text = (EXAMPLES / "lose_a_wheel.rdcd").read_text()
    report = run(text, "car7", 40, ("20s:detach 3",), obstacle="wall:1.0")
    final = {m: d["final_role"] for m, d in by_id(report).items() if m != 3}
    assert final == fresh_roles("car7", text, 3)
    assert "roles after the outside changes: every module kept its role; 1 taken away" in _summary(report)
    assert "1 × taken away" in _summary(report)


def test_lose_the_axle_its_wheels_fall_off_and_lose_their_roles() -> None:
    text = (EXAMPLES / "lose_a_wheel.rdcd").read_text()
    report = run(text, "car7", 30, ("20s:detach 1",), obstacle="wall:1.0")
    final = {m: d["final_role"] for m, d in by_id(report).items() if m != 1}
    assert final == {**fresh_roles("car7", text, 1), 3: None, 4: None}
    line = next(x for x in _summary(report).splitlines() if x.startswith("roles after"))
    assert "module 3 LeftWheel → none, module 4 RightWheel → none; 1 taken away" in line
    assert "roles settled" in line


def test_grow_an_attached_module_joins_the_gradient() -> None:
    report = run((EXAMPLES / "grow.rdcd").read_text(), "snake5", 20, ("10s:attach 5 at 1,5,0 rot 1",))
    assert by_id(report)[5]["final_role"] == "Node"
    assert by_id(report)[5]["final_state"] == {"hops": 5}
    assert "module 5 none → Node" in _summary(report)
    modules = by_id(report)
    assert [modules[m]["final_state"]["hops"] for m in range(6)] == [0, 1, 2, 3, 4, 5]


def test_same_seed_same_story() -> None:
    a = run((EXAMPLES / "move_one.rdcd").read_text(), "random4-seed109", 6, seed=3)
    b = run((EXAMPLES / "move_one.rdcd").read_text(), "random4-seed109", 6, seed=3)
    assert a["events"] == b["events"] and a["connections"] == b["connections"]


def test_a_copied_run_keeps_its_own_structure() -> None:
    """The debugger steps back by copying the run (copy.deepcopy, hooks set again): the copy's
    structure is the one at the copy, and it changes as the original did."""
    import copy

    from sim.run import Run

    program = program_of((EXAMPLES / "move_one.rdcd").read_text())
    original = Run(program, load_config("random4-seed109"),
                   Options(world="lattice", obstacle="none", duration=6))
    original.advance_chunk()
    saved = copy.deepcopy(original)
    saved.hook_events()
    original.run_to_end()
    assert saved.structure.modules[2].position == (2, 1, 1)
    assert original.structure.modules[2].position == (2, 0, 0)
    saved.run_to_end()
    assert saved.structure.modules == original.structure.modules
    assert saved.structure.links() == original.structure.links()
    assert [e for e in saved.events if e["t"] > 0.5] == [e for e in original.events if e["t"] > 0.5]
