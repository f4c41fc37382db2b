"""The recording of a structure that changes: modules that move, appear and go, latches, and the
structure's events on their source lines (docs/replay.md "Structures that change")."""

from __future__ import annotations

import numpy as np
import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim import params
from sim.config import load_config
from sim.geometry import lattice_to_world
from sim.replay.page import render_page, replay_data
from sim.replay.recording import CHANNELS, PRESENT, Recording
from sim.replay.sources import SourceIndex
from sim.run import Options, simulate
from tests.conftest import EXAMPLES
from tests.replay.helpers import page_data, unpack
from vm.lattice.outside import parse_all


def _run(example: str, config: str, world: str, duration: float, changes: list[str] = ()) -> tuple:
    text = (EXAMPLES / example).read_text(encoding="utf-8")
    program = compile_model(check_text(text).model, text=text)
    structure = load_config(config)
    recording = Recording(structure, SourceIndex(program, text), duration)
    options = Options(world=world, config=config, obstacle="none", duration=duration, recording=recording,
                      outside_changes=parse_all(list(changes)))
    report = simulate(program, structure, options)
    return recording, report, program, structure, text


def _rows(recording: Recording) -> np.ndarray:
    return np.array(recording.rows).reshape(len(recording.rows), -1, CHANNELS)


def _line(text: str, words: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if words in line)


@pytest.fixture(scope="module")
def move_one() -> tuple:
    return _run("move_one.rdcd", "random4-seed109", "lattice", 4.0)


def test_a_carried_module_goes_round_the_turning_joint_to_its_final_cell(move_one: tuple) -> None:
    recording, report, _, structure, _ = move_one
    rows = _rows(recording)
    mm = params.LATTICE_UNIT * 1000
    lift = rows[0, recording.ids.index(0), 2]  # module 0 sits at the origin
    for m in report["modules"]:  # every module ends at its final cell
        x, y, z = (np.array(m["final_lattice"]) * mm).round()
        assert np.allclose(rows[-1, recording.ids.index(m["id"]), :3], (x, y, z + lift), atol=1)
    assert report["modules"][2]["final_lattice"] == [2, 0, 0]
    start, end = (rows[0, 2, :3]), rows[-1, 2, :3]
    assert not np.allclose(start, end)
    pivot = rows[0, 1, :3]
    radius = np.linalg.norm(start - pivot)
    turning = [r[2, :3] for r in rows
               if not np.allclose(r[2, :3], start) and not np.allclose(r[2, :3], end, atol=1)]
    assert len(turning) >= 5, "the turn is not shown while it takes the joint's time"
    for centre in turning:  # on the circle about the turning module, not a jump
        assert abs(np.linalg.norm(centre - pivot) - radius) < 2
    assert rows[:, :, PRESENT].all()


def test_structure_events_are_recorded_on_the_lines_of_their_actions(move_one: tuple) -> None:
    recording, _, _, _, text = move_one
    by_kind = {e[2]: e for e in recording.events}
    assert by_kind["rotation_start"][5] == _line(text, "self.turnQuarters(1)")
    assert by_kind["rotation_end"][5] == _line(text, "self.turnQuarters(1)")
    assert by_kind["connect"][5] == _line(text, "if (self.connect(0))")
    assert by_kind["disconnect"][5] == _line(text, "self.disconnect(4)")
    assert "carrying 2" in by_kind["rotation_start"][6]


def test_latches_over_time_end_as_the_report_connections(move_one: tuple) -> None:
    recording, report, _, _, _ = move_one
    latched: set = set()
    for _t, a, ap, b, bp, on in recording.links:
        (latched.add if on else latched.discard)((a, ap, b, bp))
    assert sorted(list(k) for k in latched) == report["connections"]
    assert [0.0] * 3 == [link[0] for link in recording.links[:3]]  # the start's latches at t = 0
    opened = [link for link in recording.links if not link[5]]
    assert opened and opened[0][1:5] == [1, 7, 2, 4] and opened[0][0] > 1.0


def test_the_page_carries_presence_latches_and_final_cells(move_one: tuple) -> None:
    recording, report, program, structure, _ = move_one
    data = page_data(render_page(replay_data(recording, program, structure, report, "move_one.rdcd")))
    assert data["poses"]["channels"] == CHANNELS
    table = unpack(data["poses"]["data"], data["poses"]["count"], len(data["modules"]) * CHANNELS)
    assert np.array_equal(table, np.array(recording.filled_rows()).reshape(table.shape))
    assert data["links"] == recording.links
    assert data["modules"][2]["final_lattice"] == [2, 0, 0] and data["modules"][2]["lattice"] != [2, 0, 0]


def test_a_module_attached_appears_and_one_detached_goes_in_the_lattice_world() -> None:
    changes = ["1s:attach 5 at 1,5,0 rot 1", "3s:detach 5"]
    recording, report, program, structure, _ = _run("grow.rdcd", "snake5", "lattice", 4.0, changes)
    assert recording.ids == [0, 1, 2, 3, 4, 5] and 5 not in structure.modules
    rows = _rows(recording)
    times = np.array(recording.times)
    present = rows[:, 5, PRESENT]
    # a change at 1 s happens in the world's tick after the sample at 1 s: the next sample shows it
    assert not present[times < 1.0].any() and present[(times > 1.05) & (times <= 3.0)].all()
    assert not present[times > 3.05].any()
    assert rows[:, :5, PRESENT].all()
    x, y, z = lattice_to_world((1, 5, 0))
    here = rows[(times > 1.05) & (times <= 3.0), 5, :3]
    assert np.allclose(here[:, :2], (x * 1000, y * 1000), atol=1)
    filled = np.array(recording.filled_rows()).reshape(rows.shape)
    assert np.array_equal(filled[0, 5, :PRESENT], here[0].tolist() + filled[0, 5, 3:PRESENT].tolist())
    assert filled[0, 5, PRESENT] == 0  # filled, still absent
    kinds = [(e[1], e[2]) for e in recording.events]
    assert (5, "attach") in kinds and (5, "outside") in kinds
    assert (5, "program") in kinds, "the attached module's runtime is not watched"
    assert any(link[0] >= 1.0 and 5 in (link[1], link[3]) and link[5] == 1 for link in recording.links)
    assert any(link[0] >= 3.0 and 5 in (link[1], link[3]) and link[5] == 0 for link in recording.links)
    data = replay_data(recording, program, structure, report, "grow.rdcd")
    assert [m["id"] for m in data["modules"]] == [0, 1, 2, 3, 4, 5]


def test_a_module_detached_in_the_physics_world_goes() -> None:
    recording, report, *_ = _run("lose_a_wheel.rdcd", "car7", "physics", 2.0, ["1s:detach 3"])
    rows = _rows(recording)
    times = np.array(recording.times)
    k = recording.ids.index(3)
    assert rows[times < 1.0, k, PRESENT].all() and not rows[times > 1.05, k, PRESENT].any()
    assert any(e[1] == 3 and e[2] == "outside" for e in recording.events)
    assert not any(3 in (a, b) for a, _, b, _ in report["connections"])


def test_a_module_attached_in_the_physics_world_appears_on_its_cell() -> None:
    recording, *_ = _run("grow.rdcd", "snake5", "physics", 2.0, ["1s:attach 5 at 1,5,0 rot 1"])
    rows = _rows(recording)
    times = np.array(recording.times)
    k = recording.ids.index(5)
    assert not rows[times < 1.0, k, PRESENT].any() and rows[times > 1.05, k, PRESENT].all()
    x, y, _ = lattice_to_world((1, 5, 0))
    assert np.allclose(rows[-1, k, :2], (x * 1000, y * 1000), atol=10)  # on its cell, within 1 cm
    assert (5, "program") in [(e[1], e[2]) for e in recording.events]
