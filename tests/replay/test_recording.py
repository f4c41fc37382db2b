"""The recording of a run: what it holds, that it changes nothing of the run, and its encoding."""

from __future__ import annotations

import json

import numpy as np
import pytest

from sim.replay import encode
from sim.replay.page import json_for_script, render_page, replay_data
from sim.replay.recording import CHANNELS, MAX_MODULE_SAMPLES, Recording
from sim.replay.sources import SourceIndex
from sim.run import Options, simulate
from tests.replay.helpers import SOURCE, page_data, recorded_run, unpack
from tests.sim.helpers import obstacle_program


def _without_wall_time(report: dict) -> dict:
    return {k: v for k, v in report.items() if k not in ("wall_time_s", "real_time_factor")}


@pytest.mark.parametrize("world", ["lattice", "physics"])
def test_recording_changes_nothing_of_the_run(world: str) -> None:
    from sim.config import load_config

    program = obstacle_program()
    plain = simulate(program, load_config("car7"), Options(world=world, duration=6.0, obstacle="wall:1.0"))
    _, recorded = recorded_run(world, 6.0)
    assert _without_wall_time(recorded) == _without_wall_time(plain)


@pytest.mark.parametrize("world", ["lattice", "physics"])
def test_poses_are_sampled_ten_times_a_second_for_every_module(world: str) -> None:
    recording, report = recorded_run(world, 4.0)
    modules = len(report["modules"])
    assert len(recording.times) >= 4.0 * 10
    assert all(len(row) == modules * CHANNELS for row in recording.rows)
    gaps = np.diff(recording.times)
    assert gaps.max() <= 0.1 + 1e-6
    quaternions = np.array(recording.rows).reshape(len(recording.rows), modules, CHANNELS)[:, :, 3:11]
    norms = np.linalg.norm(quaternions.reshape(-1, 4), axis=1) / 32767
    assert np.allclose(norms, 1.0, atol=2e-3)  # unit rotations, quantised


def test_physics_poses_follow_the_trajectory() -> None:
    recording, report = recorded_run("physics", 6.0)
    rows = np.array(recording.rows).reshape(len(recording.rows), -1, CHANNELS)
    centre = rows[-1, :, :2].mean(axis=0) / 1000
    x, y = report["trajectory"][-1][1:3]
    assert abs(centre[0] - x) < 0.01 and abs(centre[1] - y) < 0.01


def test_lattice_joint_turns_show_in_the_turning_hemisphere() -> None:
    recording, _ = recorded_run("lattice", 4.0)
    rows = np.array(recording.rows).reshape(len(recording.rows), -1, CHANNELS)
    turning = [i for i in range(rows.shape[1]) if len({tuple(r) for r in rows[:, i, 3:11]}) > 1]
    assert turning, "no hemisphere turned though the wheels rotate"
    assert all(len({tuple(r) for r in rows[:, i, :3]}) == 1 for i in range(rows.shape[1]))  # no module moves


def test_events_know_their_fragment_and_source_line() -> None:
    recording, report = recorded_run("physics", 20.0)
    program = obstacle_program()
    lines = SOURCE.splitlines()
    kinds = {e[2] for e in recording.events}
    assert {"program", "run", "role", "handler", "sensor", "command", "send"} <= kinds
    sends = [e for e in recording.events if e[2] == "send"]
    assert all("Wheel.stop()" in lines[e[5] - 1] for e in sends)  # the handler sends stop to the wheels
    handlers = [e for e in recording.events if e[2] == "handler"]
    assert len(handlers) == report["obstacle_detections"]
    for _, _, _, fragment, _, line, _ in handlers:
        assert "handleEvent" in lines[line - 1]
        assert program.fragments[fragment].source[0] <= line <= program.fragments[fragment].source[1]
    for _, _, _, fragment, _, line, text in (e for e in recording.events if e[2] == "program"):
        assert program.fragments[fragment].name in text and line > 0
    roles = [e for e in recording.events if e[2] == "role"]
    history = sorted((t, m["id"]) for m in report["modules"] for t, _ in m["role_history"])
    assert sorted((e[0], e[1]) for e in roles) == history


def test_packets_match_the_network_counters() -> None:
    recording, report = recorded_run("lattice", 10.0, packet_loss=0.2, seed=3)
    dropped = sum(1 for p in recording.packets if p[6])
    assert len(recording.packets) == report["messages"]["sent"]
    assert dropped == report["messages"]["dropped"] > 0
    modules = {m["id"] for m in report["modules"]}
    assert all(p[1] in modules and p[2] in modules and p[1] != p[2] for p in recording.packets)


def test_encoding_round_trips() -> None:
    recording, _ = recorded_run("physics", 3.0)
    poses = encode.poses(recording)
    table = unpack(poses["data"], poses["count"], len(recording.rows[0]))
    assert table.tolist() == recording.rows
    times = unpack(poses["times"], poses["count"], 1)[:, 0] / 1000
    assert np.allclose(times, recording.times)
    packets = encode.packets(recording)
    back = unpack(packets["data"], packets["count"], 7)
    assert [tuple(r[1:3]) for r in back.tolist()] == [(p[1], p[2]) for p in recording.packets]


def test_long_runs_lower_the_sample_rate_and_say_so() -> None:
    from sim.config import load_config

    structure = load_config("car17-wide")
    recording = Recording(structure, SourceIndex(obstacle_program(), SOURCE), 3600.0)
    assert recording.hz < 10
    assert 3600 * recording.hz * len(structure.modules) <= MAX_MODULE_SAMPLES + 1
    assert any("sampled every" in note for note in recording.finish_notes())


def test_script_text_cannot_end_the_data_element() -> None:
    hostile = {"lines": ["// </script><script>window.pwned = 1</script>", "<!-- x", "a & b \u2028"]}
    text = json_for_script(hostile)
    assert "<" not in text and ">" not in text and "&" not in text
    assert json.loads(text) == hostile


def test_page_is_one_file_with_a_strict_policy() -> None:
    recording, report = recorded_run("lattice", 2.0)
    from sim.config import load_config

    html = render_page(replay_data(recording, obstacle_program(), load_config("car7"), report, "car.rdcd"))
    assert html.count("<script") == 2  # the data and the viewer, nothing else
    assert "src=" not in html.split("<script>")[0]  # no external resource before the bundle
    assert "default-src 'none'" in html and "unsafe-inline" not in html and "unsafe-eval" not in html
    data = page_data(html)
    assert data["source"]["lines"] == SOURCE.split("\n")[:-1]
    assert [m["id"] for m in data["modules"]] == [m["id"] for m in report["modules"]]


@pytest.mark.parametrize("world", ["lattice", "physics"])
@pytest.mark.parametrize("duration", [0.01, 0.333])
def test_short_odd_durations_end_and_match_the_plain_run(world: str, duration: float) -> None:
    from sim.config import load_config

    plain = simulate(obstacle_program(), load_config("car7"), Options(world=world, duration=duration))
    recording, recorded = recorded_run(world, duration, obstacle="none")
    assert _without_wall_time(recorded) == _without_wall_time(plain)
    assert recording.times[0] == 0.0 and len(recording.times) >= 2


def test_stored_slots_are_named_after_the_fragment_that_stored_them() -> None:
    recording, _ = recorded_run("physics", 5.0)
    program = obstacle_program()
    names = recording.stored_fragments()
    for mid, runtime in recording.runtimes.items():
        assert len(names[mid]) == len(runtime.store.slots)
        for name, slot in zip(names[mid], runtime.store.slots, strict=True):
            fragment = program.fragment(name.split(" (")[0])
            assert slot.code in fragment.code
            assert name.endswith(f"({slot.kind})") or slot.kind == "program"
    assert any(name.endswith("(handler)") for stored in names.values() for name in stored)


def test_events_and_packets_beyond_their_caps_are_counted_in_a_note(monkeypatch: pytest.MonkeyPatch) -> None:
    import sim.replay.recording as recording_module

    monkeypatch.setattr(recording_module, "MAX_EVENTS", 5)
    monkeypatch.setattr(recording_module, "MAX_PACKETS", 7)
    recording, report = recorded_run("lattice", 3.0)
    assert len(recording.events) == 5 and len(recording.packets) == 7
    assert recording.dropped_packets == report["messages"]["sent"] - 7 > 0
    notes = " ".join(recording.finish_notes())
    assert "events after the first 5 are not shown" in notes and "packets after the first 7" in notes
