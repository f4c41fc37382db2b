"""One error per mistake: a syntax error is reported without the checker's diagnostics that only
follow from recovery's repair (rdcd_core/syntax/consequences.py)."""

from __future__ import annotations

import pytest

from rdcd_core.frontend import check_text

WHEEL = """abstract role Wheel {{
  abstract constant side;
  self.center_position == EAST_WEST;
  {member}
}}
role RightWheel extends Wheel {{ constant side := {side}; }}
deployment {{ RightWheel }}
"""


def codes(text: str) -> list[str]:
    return [d.code for d in check_text(text).diagnostics if d.severity.name == "ERROR"]


@pytest.mark.parametrize("bad", ["#", "@", "$", "?"])
def test_a_bad_character_between_arguments_is_one_error(bad):
    text = WHEEL.format(member=f"command go(speed) {{ self.turnContinuously(speed {bad} side); }}", side="1")
    assert codes(text) == ["E001"]


def test_the_issue_example_without_the_arity_error():
    text = WHEEL.format(member="command go(speed) { self.turnContinuously(speed # side); }", side="1")
    messages = [d.message for d in check_text(text).diagnostics]
    assert len(messages) == 1 and "unexpected character '#'" in messages[0]


def test_a_broken_constant_definition_does_not_also_report_it_missing():
    text = WHEEL.format(member="", side="1").replace("constant side := 1", "constant # := EAST")
    assert codes(text) == ["E001"]  # not also E110, "RightWheel does not define constant 'side'"


def test_one_syntax_error_per_statement():
    broken = "EAST_WEST;\n  sizeof(self.connected(UP)) =# 1;"  # '=' and '#': one mistake
    text = WHEEL.format(member="", side="1").replace("EAST_WEST;", broken)
    assert len(codes(text)) == 1


def test_other_mistakes_are_still_reported():
    text = WHEEL.format(member="command go(speed) { self.turnContinuously(speed # side); }\n"
                               "  command halt() { self.turnContinuously(1, 2); }", side="1")
    found = codes(text)
    assert found.count("E001") == 1 and "E302" in found  # the second call's arity is a mistake of its own
    text = "role A { self.y( > 0; }\nrole A { }\ndeployment { A, B }"
    found = codes(text)
    assert "E101" in found and "E501" in found  # the unknown role is not a consequence


def test_programs_without_syntax_errors_are_untouched():
    text = WHEEL.format(member="command go(speed) { self.turnContinuously(speed, side); }", side="1")
    assert codes(text) == ["E302"]
