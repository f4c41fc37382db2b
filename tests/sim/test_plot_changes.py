"""What the plot and the summary say of a structure that changed (sim/plot_changes.py, and
summary_line in sim/structure_report.py)."""

from __future__ import annotations

from pathlib import Path

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.plot import plot_report
from sim.plot_changes import CHANGES_LISTED, changes_text, structure_changes
from sim.run import Options, simulate
from sim.structure_report import summary_line
from tests.conftest import EXAMPLES
from vm.lattice.outside import parse_all


def _report(example: str, config: str, duration: float, changes: list[str] = ()) -> dict:
    text = (EXAMPLES / example).read_text(encoding="utf-8")
    program = compile_model(check_text(text).model, text=text)
    options = Options(world="lattice", config=config, obstacle="none", duration=duration,
                      outside_changes=parse_all(list(changes)))
    return simulate(program, load_config(config), options)


def test_the_changes_of_move_one_are_listed_in_time_order() -> None:
    report = _report("move_one.rdcd", "random4-seed109", 3.0)
    changes = structure_changes(report)
    assert [kind for _, kind, _ in changes] == ["rotation_end", "connect", "disconnect"]
    text = changes_text(changes)
    assert text.startswith("structure changes: ") and "1 turned +1" in text
    assert "latch 2.0-3.7" in text and "unlatch 1.7-2.4" in text
    assert summary_line(report) == "structure: 1 latched, 1 unlatched, 1 turn done"


def test_an_outside_change_is_named_as_given_in_the_summary_and_the_plot() -> None:
    report = _report("lose_a_wheel.rdcd", "car7", 2.0, ["1s:detach 3"])
    assert summary_line(report) == "structure: 1 outside change (1s:detach 3)"
    assert changes_text(structure_changes(report)) == "structure changes: 1 s: detach 3"


def test_a_long_story_is_cut_and_counted() -> None:
    events = [{"t": float(i), "module": 1, "kind": "connect",
               "detail": {"link": [1, 0, 2, 5]}} for i in range(CHANGES_LISTED + 4)]
    text = changes_text(structure_changes({"events": events}))
    assert text.count("latch 1.0-2.5") == CHANGES_LISTED and text.endswith("+4 more")
    assert changes_text([]) == "structure changes: "
    many = {"structure_changes": {"outside": 5}, "events": [
        {"t": 1.0, "module": i, "kind": "outside", "detail": {"change": f"1s:stop {i}"}} for i in range(5)]}
    assert summary_line(many) == "structure: 5 outside changes (1s:stop 0, 1s:stop 1, 1s:stop 2, +2 more)"


def test_the_plot_of_a_changed_structure_is_written(tmp_path: Path) -> None:
    report = _report("move_one.rdcd", "random4-seed109", 3.0)
    # a path as the physics world gives it, so that the changes are marked on it
    report["trajectory"] = [[t / 10, 0.08 + t / 1000, 0.02, 0.0] for t in range(31)]
    report["modules"][3]["final_lattice"] = None  # as if taken away: not drawn at the end
    out = tmp_path / "plot.png"
    plot_report(report, None, str(out))
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
