"""The state part of the simulation report (sim/state_report.py): final values by name, the history
of changes, role state only while its role is played, values that never settled; and the real
``rdcd simulate`` in both worlds."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.compiler.program import CompiledProgram, StateEntry
from sim import state_report as sr
from sim.report import summary
from tests.cli.helpers import rdcd
from tests.conftest import EXAMPLES
from tests.state.state_harness import hop_distances, structure

NEVER_SETTLES = """\
// a counter that counts forever: 0, 1, ..., 100, 0, 1, ... (never settles)
state ticks := 0;
role Node {
  behavior count() {
    if (ticks == 100) ticks := 0; else ticks := ticks + 1;
  }
}
deployment { Node }
"""


def program(*states: StateEntry) -> CompiledProgram:
    return CompiledProgram([], [], [], 64, [], states=list(states))


SIZE = StateEntry("size", 0, 1, None, True)
STEPS = StateEntry("steps", 1, 5, "Walker", False, ("Runner", "Walker"))


def runtime(state: list[int], history: list[tuple[float, int, int]]) -> SimpleNamespace:
    return SimpleNamespace(state=state + [0] * (32 - len(state)), state_history=history)


def test_final_state_names_every_module_state_and_the_role_state_of_the_role_played() -> None:
    rt = runtime([7, 3], [(0.01, 0, 1), (0.5, 1, 5), (0.7, 1, 3), (1.234567, 0, 7)])
    walker = sr.module_fields(program(SIZE, STEPS), rt, "Walker")
    assert walker["final_state"] == {"size": 7, "steps": 3}
    assert walker["state_history"] == [[0.01, "size", 1], [0.5, "steps", 5], [0.7, "steps", 3],
                                       [1.235, "size", 7]]
    assert walker["state_history_omitted"] == 0
    # a sub-role has its parent's role state; another role, or none, does not
    assert sr.module_fields(program(SIZE, STEPS), rt, "Runner")["final_state"] == {"size": 7, "steps": 3}
    for other in ("Sitter", None):
        assert sr.module_fields(program(SIZE, STEPS), rt, other)["final_state"] == {"size": 7}


def test_values_are_signed_and_history_of_unknown_bytes_is_left_out() -> None:
    rt = runtime([-128, 127], [(0.1, 0, -128), (0.2, 9, 4)])
    fields = sr.module_fields(program(SIZE), rt, None)
    assert fields["final_state"] == {"size": -128}
    assert fields["state_history"] == [[0.1, "size", -128]]


def test_the_history_is_bounded_and_says_how_much_it_left_out() -> None:
    n = sr.MAX_STATE_HISTORY + 123
    rt = runtime([n % 100], [(i / 100, 0, i % 100) for i in range(n)])
    fields = sr.module_fields(program(SIZE), rt, None)
    assert len(fields["state_history"]) == sr.MAX_STATE_HISTORY
    assert fields["state_history_omitted"] == 123
    assert fields["state_history"][-1] == [round((n - 1) / 100, 3), "size", (n - 1) % 100]


def test_settle_window_is_a_tenth_of_the_run_and_at_least_a_second() -> None:
    assert sr.settle_window(60) == 6.0
    assert sr.settle_window(5) == 1.0
    assert sr.settle_window(0.5) == 0.5


def test_unsettled_names_the_states_that_changed_in_the_window_and_where() -> None:
    modules = [{"id": 0, "state_history": [[1.0, "hops", 0], [59.0, "size", 7]]},
               {"id": 3, "state_history": [[53.9, "hops", 2]]},
               {"id": 7, "state_history": [[55.0, "hops", 1], [53.9, "size", 4]]}]
    found = sr.unsettled(modules, 60.0)
    assert found == [{"state": "size", "modules": [0], "last_change_s": 59.0},
                     {"state": "hops", "modules": [7], "last_change_s": 55.0}]
    assert sr.unsettled(modules, 100.0) == []


def test_summary_lines_name_settled_and_unsettled_states() -> None:
    report = {"states": [{"name": "hops"}, {"name": "size"}, {"name": "idle"}], "settle_window_s": 6.0,
              "modules": [{"id": m, "state_history": [[0.5 + m, "hops", m]]} for m in range(12)],
              "unsettled": [{"state": "hops", "modules": list(range(12)), "last_change_s": 11.5}]}
    report["modules"][0]["state_history"].append([2.25, "size", 3])
    lines = sr.summary_lines(report)
    assert lines[0] == ("state 'hops' still changing on modules 0, 1, 2, 3, 4, 5, 6, 7 and 4 more at the end "
                        "(changed in the last 6 s; not settled)")
    assert lines[1] == "state settled: size at 2.25 s, idle never changed"
    assert sr.summary_lines({"states": [], "modules": []}) == []


# ---- the real command ------------------------------------------------------------------------

def simulate(tmp_path: Path, program: str, *options: str) -> tuple[dict, str]:
    out = tmp_path / "r.json"
    done = rdcd("simulate", program, "--report", str(out), "--obstacle", "none", *options)
    assert done.returncode == 0, done.stderr
    return json.loads(out.read_text()), done.stdout


def test_count_on_car7_the_entry_module_ends_knowing_seven(tmp_path: Path) -> None:
    # exactly the command of the issue: default duration (60 s) and obstacle
    out = tmp_path / "r.json"
    done = rdcd("simulate", "--world", "lattice", str(EXAMPLES / "count.rdcd"), "--config", "car7",
                "--report", str(out))
    assert done.returncode == 0, done.stderr
    report, stdout = json.loads(out.read_text()), done.stdout
    entry = next(m for m in report["modules"] if m["id"] == report["entry"])
    assert entry["final_state"] == {"size": 7}
    assert entry["state_history"][-1][1:] == ["size", 7]
    assert report["states"] == [{"name": "size", "index": 0, "initial": 1, "owner": None, "published": True,
                                 "roles": []}]
    assert report["unsettled"] == []
    assert "state settled: size at " in stdout


@pytest.mark.parametrize("world", ["lattice", "physics"])
def test_gradient_final_state_is_the_hop_distance_in_both_worlds(tmp_path: Path, world: str) -> None:
    report, _ = simulate(tmp_path, str(EXAMPLES / "gradient.rdcd"), "--world", world, "--config", "car7",
                         "--duration", "3")
    expected = hop_distances(structure("car7"))
    assert {m["id"]: m["final_state"]["hops"] for m in report["modules"]} == expected


def test_lowest_reports_role_free_module_state(tmp_path: Path) -> None:
    report, _ = simulate(tmp_path, str(EXAMPLES / "lowest.rdcd"), "--world", "lattice", "--config", "car7",
                         "--duration", "5")
    lowest = min(m["lattice"][2] for m in report["modules"])
    for m in report["modules"]:
        assert m["final_state"] == {"lowest": lowest}
        assert m["final_role"] == ("Bottom" if m["lattice"][2] == lowest else "Upper")


def test_a_program_that_never_settles_ends_at_its_duration_and_says_so(tmp_path: Path) -> None:
    source = tmp_path / "ticks.rdcd"
    source.write_text(NEVER_SETTLES)
    report, stdout = simulate(tmp_path, str(source), "--world", "lattice", "--config", "car7",
                              "--duration", "8")
    assert report["duration_s"] == 8
    assert report["settle_window_s"] == 1.0
    [open_state] = report["unsettled"]
    assert open_state["state"] == "ticks"
    assert open_state["modules"] == sorted(m["id"] for m in report["modules"])
    assert 7.0 < open_state["last_change_s"] <= 8.0
    assert "state 'ticks' still changing on modules 0, 1, 2, 3, 4, 5, 6 at the end" in stdout
    for m in report["modules"]:
        assert len(m["state_history"]) <= sr.MAX_STATE_HISTORY
        assert 0 <= m["final_state"]["ticks"] <= 100
    assert "still changing" in summary(report)


@settings(max_examples=200, deadline=None)
@given(st.floats(0.5, 3600), st.lists(st.lists(st.tuples(st.floats(0, 1), st.sampled_from([0, 1]),
                                                         st.integers(-128, 127)), max_size=40), max_size=6))
def test_unsettled_is_exactly_a_change_in_the_window(duration: float, modules: list) -> None:
    entries = program(SIZE, StateEntry("hops", 1, 127, None, True))
    report_modules = []
    for mid, changes in enumerate(modules):
        history = sorted((round(f * duration, 3), i, v) for f, i, v in changes)
        rt = runtime([0, 0], history)
        report_modules.append({"id": mid, **sr.module_fields(entries, rt, None)})
        assert len(report_modules[-1]["state_history"]) == min(len(history), sr.MAX_STATE_HISTORY)
    since = duration - sr.settle_window(duration)
    found = {u["state"]: u["modules"] for u in sr.unsettled(report_modules, duration)}
    for name, index in (("size", 0), ("hops", 1)):
        late = [mid for mid, changes in enumerate(modules)
                if any(round(f * duration, 3) > since + 1e-9 for f, i, _ in changes if i == index)]
        assert found.get(name, []) == late


def test_a_role_state_is_kept_by_sub_roles_and_mixin_applications_not_by_other_roles() -> None:
    from rdcd_core.compiler import compile_model
    from rdcd_core.frontend import check_text

    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    text = text.replace("abstract role Wheel {\n", "abstract role Wheel {\n  state stops := 0;\n", 1)
    text = text.replace("  command stop() {\n", "  command stop() {\n    stops := stops + 1;\n", 1)
    result = check_text(text)
    assert not result.model.has_errors
    [stops] = compile_model(result.model, text=text).states
    assert stops.owner == "Wheel"
    assert stops.roles == ("LeftWheel", "Reverse@LeftWheel", "Reverse@RightWheel", "RightWheel", "Wheel")
    for role in stops.roles:
        assert sr.plays(stops, role)
    for role in ("Axle", "Reverse", None):
        assert not sr.plays(stops, role)
