"""Sequences: syntax, formatting, the names check and the run through the lattice model
(docs/reconfiguration.md)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from rdcd_core.diagnostics import all_codes
from rdcd_core.formatter import format_text
from rdcd_core.frontend import check_text
from rdcd_core.syntax import ast, parse
from rdcd_core.syntax.ast import strip_spans

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EIGHT = (EXAMPLES / "eight_to_snake.rdcd").read_text()

ROLES = """role Front { self.center_position == UP_DOWN; self.y() > 0; }
role LeftFront { self.center_position == EAST_WEST; self.x() > 0; self.y() > 0; }
role Rest { self.center_position == NORTH_SOUTH || self.y() < 0 || self.x() < 0; }
"""


def codes(text: str, config: str | None = None) -> list[str]:
    return [d.code for d in check_text(text, config=config).diagnostics]


def test_a_sequence_parses_into_steps_and_parallel_blocks() -> None:
    result = parse(ROLES + "sequence s(car7) { Front.turnQuarters(1); parallel { "
                   "LeftFront.turnQuarters(-1); Rest(self.x() < 0 && self.y() > 0).waitUntil(1 == 1); "
                   "} }\ndeployment { Front, LeftFront, Rest }")
    assert result.ok, result.diagnostics
    (sequence,) = result.program.sequences
    assert sequence.name.text == "s" and sequence.config is not None and sequence.config.text == "car7"
    first, block = sequence.items
    assert isinstance(first, ast.SeqStep) and first.action.text == "turnQuarters"
    assert isinstance(block, ast.SeqParallel) and len(block.steps) == 2
    assert block.steps[1].condition is not None


def test_formatting_keeps_the_tree_and_is_idempotent() -> None:
    text = (ROLES + "sequence s { Front.turnQuarters( 1 ) ; parallel{LeftFront.turnQuarters(-1);} }\n"
            "deployment { Front, LeftFront, Rest }")
    formatted = format_text(text)
    assert formatted is not None and format_text(formatted) == formatted
    assert strip_spans(parse(formatted).program) == strip_spans(parse(text).program)
    assert "  parallel {\n    LeftFront.turnQuarters(-1);\n  }" in formatted


def test_every_sequence_code_is_triggered_by_its_example() -> None:
    for info in all_codes():
        if info.code[1] == "8":
            assert info.code in codes(info.example), info.code


def test_the_example_checks_clean_and_its_end_shape_is_the_snake() -> None:
    result = check_text(EIGHT)
    assert not result.diagnostics, result.diagnostics
    trace = result.traces[0]
    links = {(k.a, k.b) for k in trace.final.links()}
    assert links == {(0, 2), (0, 1), (1, 3), (3, 5), (4, 6), (5, 6)}  # the chain 2-0-1-3-5-6-4
    assert [r.module for r in trace.results] == [2, 4]
    assert "links:" in trace.results[0].after


def test_the_config_option_wins_over_the_one_the_sequence_names() -> None:
    # car7's wheel 3 holds UpperLeft, but its connector 0 holds nothing
    assert codes(EIGHT, config="car7") == ["E815"]
    assert "E810" in codes(EIGHT, config="snake1")  # no module of snake1 holds UpperLeft


def test_parallel_steps_may_share_the_far_end_of_their_latches() -> None:
    # both open a latch of module 3, which does not act: independent (they run at once)
    text = EIGHT.replace("  UpperLeft.disconnect(0);\n  LowerRight.disconnect(6);",
                         "  parallel { UpperLeft.disconnect(0); LowerRight.disconnect(6); }")
    assert text != EIGHT
    assert codes(text) == []


@pytest.mark.parametrize("block", [
    "UpperLeft.waitUntil(1 == 1); UpperLeft.disconnect(0);",  # one module acts twice
    "UpperLeft.disconnect(0); Hub(self.x() == 2).waitUntil(1 == 1);",  # acts at the other's far end
    "Hub(self.x() == 2).waitUntil(1 == 1); UpperLeft.disconnect(0);",  # the same, written the other way
])
def test_parallel_steps_on_the_same_module_are_refused(block: str) -> None:
    text = EIGHT.replace("  UpperLeft.disconnect(0);\n  LowerRight.disconnect(6);",
                         f"  parallel {{ {block} }}")
    assert text != EIGHT
    assert "E816" in codes(text)


@pytest.mark.parametrize("step, code", [
    ("Nobody.connect(0);", "E802"),
    ("UpperLeft.jump(0);", "E803"),
    ("UpperLeft.connect(1);", "E803"),
    ("UpperLeft.connect(self.x());", "E803"),
    ("UpperLeft.turnQuarters(0);", "E803"),
    ("UpperLeft.turnQuarters(9);", "E803"),
    ("UpperLeft(self.connect(0)).waitUntil(1 == 1);", "E803"),
    ("UpperLeft.waitUntil();", "E803"),
    ("UpperLeft.disconnect(2);", "E815"),
    ("UpperLeft.connect(0);", "E815"),
    ("UpperLeft.turnQuarters(1);", "E813"),
])
def test_bad_steps(step: str, code: str) -> None:
    text = EIGHT.replace("  UpperLeft.disconnect(0);\n", f"  {step}\n")
    assert code in codes(text)


def test_a_split_is_refused_at_the_step() -> None:
    text = EIGHT.replace("  LowerRight.disconnect(6);\n",
                         "  LowerRight.disconnect(6);\n  Side(self.x() == 1).disconnect(6);\n")
    found = check_text(text).diagnostics
    assert [d.code for d in found] == ["E814"]
    assert text[found[0].span.start:found[0].span.end].startswith("Side(")


def test_a_sequence_named_like_a_state_and_a_duplicate() -> None:
    assert "E801" in codes("state s := 0;\n" + EIGHT.replace("eightToSnake(", "s("))
    twice = EIGHT.replace("deployment {", "sequence eightToSnake { }\ndeployment {")
    assert "E801" in codes(twice)


@pytest.mark.parametrize("suffix", ["_par", "_t", "_k"])
def test_a_state_named_like_the_sequence_s_own_is_an_error_not_silently_shared(suffix: str) -> None:
    text = f"state eightToSnake{suffix} := 0;\n" + EIGHT
    found = [d for d in check_text(text).diagnostics if d.code == "E801"]
    assert len(found) == 1 and f"'eightToSnake{suffix}' is the name sequence" in found[0].message
    assert found[0].span.start == text.index(f"eightToSnake{suffix}")


def test_an_unknown_configuration_is_a_diagnostic_and_a_bad_option_a_usage_error(tmp_path: Path) -> None:
    assert "E804" in codes(EIGHT.replace("(eight7)", "(nosuchconfig)"))
    program = tmp_path / "p.rdcd"
    program.write_text(EIGHT)
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", "--config", "nosuch", str(program)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "--config" in done.stderr and "Traceback" not in done.stderr
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", "--config", "car7", str(program)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 1 and "E815" in done.stdout


def test_a_sequence_without_configuration_is_checked_by_names_only() -> None:
    assert codes(EIGHT.replace("(eight7)", "")) == []


def test_roles_that_read_published_values_make_the_rest_unchecked() -> None:
    text = "state r := 0;\n" + EIGHT.replace("self.x() == 1;\n  self.y() == 1;", "r == max(neighbours.r);")
    assert "W810" in codes(text)


def test_many_steps_are_refused() -> None:
    body = "UpperLeft.waitUntil(1 == 1);\n" * 61
    assert "E803" in codes(EIGHT.replace("  UpperLeft.disconnect(0);\n", body))


def test_hovering_a_step_shows_the_module_and_the_structure_after_it() -> None:
    from rdcd_core.ide.analysis import analyze
    from rdcd_core.ide.hover import hover

    analysis = analyze(EIGHT)
    found = hover(analysis, EIGHT.index("LowerRight.disconnect") + 3)
    assert found is not None and "module 4 acts" in found.markdown
    assert "links: 0.3-2.4 0.7-1.6 1.2-3.5 3.3-5.4 4.2-6.5 5.0-6.1" in found.markdown
    unchecked = EIGHT.replace("(eight7)", "")
    found = hover(analyze(unchecked), unchecked.index("LowerRight.disconnect") + 3)
    assert found is not None and "no starting configuration" in found.markdown


def test_only_rollback_may_follow_the_configuration() -> None:
    assert codes(EIGHT.replace("(eight7) {", "(eight7) rollback {")) == []
    assert "E803" in codes(EIGHT.replace("(eight7) {", "(eight7) undo {"))
    formatted = format_text(EIGHT.replace("(eight7) {", "(eight7)   rollback{"))
    assert formatted is not None and "sequence eightToSnake(eight7) rollback {" in formatted


def test_a_role_invariant_on_the_progress_fits() -> None:
    # once one discovery fragment of 213 bytes (E807); state-dependent discovery is split now
    text = EIGHT.replace("role Hub {", "role Spine {\n  self.center_position == NORTH_SOUTH;\n"
                         "  sizeof(self.total_connected()) == 2;\n  eightToSnake == 2;\n}\n\nrole Hub {")
    text = text.replace("deployment { UpperLeft, LowerRight, Hub, Side }",
                        "deployment { UpperLeft, LowerRight, Spine, Hub, Side }")
    result = check_text(text)
    assert not result.has_errors, [d.code for d in result.diagnostics]
    assert not [d for d in result.diagnostics if d.code in ("E601", "W601")]


@pytest.mark.parametrize("steps, rollback, says", [
    (1, False, ["0 before the first, 1 when the sequence is done"]),
    (1, True, ["1 when the sequence is done", "after a step failed): 2: rolled back"]),
    (2, True, ["3 says to undo step 1, 4: rolled back"]),
    (3, True, ["3 when the sequence is done", "4..5 say which step to undo next (4: step 2, 5: step 1), "
               "6: rolled back"]),
])
def test_hovering_the_progress_says_what_its_values_mean(steps: int, rollback: bool, says: list[str]) -> None:
    from rdcd_core.ide.analysis import analyze
    from rdcd_core.ide.hover import hover

    body = " ".join(["R(self.x() == 1).connect(0);"] * steps)
    text = (f"role R {{ self.x() >= 0; behavior b() {{ if (s == {steps}) self.setLed(1); }} }}\n"
            f"sequence s {'rollback ' if rollback else ''}{{ {body} }}\ndeployment {{ R }}\n")
    found = hover(analyze(text), text.index(f"s == {steps}"))
    assert found is not None and found.markdown.startswith("**progress** of sequence `s`")
    assert "module state, published" in found.markdown and "byte" not in found.markdown
    for part in says:
        assert part in found.markdown, found.markdown
