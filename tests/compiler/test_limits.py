"""Target limits of docs/language.md, reported at the construct that causes them."""

from __future__ import annotations

import re

import pytest

from rdcd_core.compiler import target_diagnostics
from rdcd_core.compiler.roletable import build_role_table
from rdcd_core.frontend import check_text
from vm.isa.opcodes import ROLE_IDS


def codes_of(text: str, **options) -> list[str]:
    result = check_text(text)
    assert not any(d.severity == 1 and not d.code.startswith("E6") for d in result.diagnostics)
    return [d.code for d in target_diagnostics(result.model, **options)]


def observed_roles_program(concrete: int) -> str:
    roles = ["abstract role A { }", "abstract role B { }",
             "role R0 extends A { connected_role(DOWN, A) > 0; }",
             "role R1 extends A { connected_role(DOWN, B) > 0; }"]
    roles += [f"role R{i} extends A {{ self.x() > {i}; }}" for i in range(2, concrete)]
    deployment = ", ".join(f"R{i}" for i in reversed(range(concrete)))
    return "\n".join(roles) + f"\ndeployment {{ {deployment} }}"


def role_ids_the_checker_counts(text: str) -> int | None:
    """The number in E120's message, None without E120."""
    found = [d.message for d in check_text(text).diagnostics if d.code == "E120"]
    return int(re.search(r"needs (\d+) role identifiers", found[0]).group(1)) if found else None


MIXINS = ("\n".join(f"role R{i} {{ self.x() == {i}; startup s() {{ self.assumeRole(M, {{ }}); }} }}"
                    for i in range(7))
          + "\nrole M modifies Module { }\nrole N modifies R0 { }\n"
          "role Q extends R0 { startup t() { self.assumeRole(N, { }); } }\n")


@pytest.mark.parametrize(("text", "ids"), [
    (observed_roles_program(13), 15),  # 13 concrete + A + B
    (observed_roles_program(12), 14),
    (MIXINS + "deployment { " + ", ".join(f"R{i}" for i in range(7)) + ", Q }", None),
    (MIXINS + "deployment { " + ", ".join(f"R{i}" for i in range(6)) + " }", 13),
])
def test_the_checker_counts_the_role_ids_of_the_role_table(text: str, ids: int | None) -> None:
    """E120 (the checker) is the only report of this limit (E602 is retired): its count must be
    the compiler's role table, on both sides of the limit."""
    table = build_role_table(check_text(text).model)
    counted = role_ids_the_checker_counts(text)
    assert counted == (len(table.entries) if len(table.entries) > ROLE_IDS else None)
    if ids is not None:
        assert len(table.entries) == ids
    if counted is None:
        assert codes_of(text) == []


def test_behaviours_share_the_command_table():
    """Counting entries is the checker's (E121); the compiler reports a command that finds no free
    number because the commands it shares with other roles hold them (E603)."""
    methods = " ".join(f"command c{i}() {{ self.setLed({i}); }}" for i in range(4))
    methods += " behavior b1() { self.sleep(); } behavior b2() { self.sleep(); }"
    text = f"role A {{ self.x() > 0; {methods} }}\ndeployment {{ A }}"
    assert [d.code for d in check_text(text).diagnostics] == ["E121"]
    shared = ("role A { self.x() > 0; command a() { } command b() { } command c() { } command d() { }\n"
              "  command e() { } }\nrole B { self.x() < 0; command a() { } command f() { } }\n"
              "role C { self.x() == 0; command b() { } command c() { } command d() { } command e() { }\n"
              "  command f() { } }\ndeployment { A, B, C }")
    diagnostics = target_diagnostics(check_text(shared).model)
    assert [d.code for d in diagnostics] == ["E603", "E603"]
    assert {shared[d.span.start:d.span.end] for d in diagnostics} == {"f"}
    assert "a command keeps one number in every role that has it" in diagnostics[0].message


def test_eleven_stored_programs_is_a_warning():
    handlers = " ".join(f"self.handleEvent(EVENT_PROXIMITY_{k}, {{ self.setLed(1); }});" for k in range(8))
    commands = " ".join(f"command c{i}() {{ self.setLed({i}); }}" for i in range(3))
    text = f"role A {{ self.x() > 0; startup s() {{ {handlers} }} {commands} }}\ndeployment {{ A }}"
    assert "W602" in codes_of(text)


def test_a_handler_installed_again_for_its_event_takes_no_further_slot():
    handlers = " ".join(f"self.handleEvent(EVENT_PROXIMITY_{k}, {{ self.setLed({n}); }});"
                        for k in range(4) for n in range(2))  # 8 installs, 4 events
    commands = " ".join(f"command c{i}() {{ self.setLed({i}); }}" for i in range(3))
    text = f"role A {{ self.x() > 0; startup s() {{ {handlers} }} {commands} }}\ndeployment {{ A }}"
    assert "W602" not in codes_of(text)  # 3 commands + 4 handlers = 7 stored programs


def test_oversized_code_that_cannot_be_split_is_reported():
    leds = " ".join(f"self.setLed({i});" for i in range(30))
    text = (f"role A {{ self.x() > 0; startup s() {{ if (connected_role(UP, A) > 0) {{ {leds} }} }} }}"
            "\ndeployment { A }")
    assert "E601" in codes_of(text)
    handler = text.replace("if (connected_role(UP, A) > 0) {", "self.handleEvent(EVENT_PROXIMITY_1, {")
    assert codes_of(handler.replace("} } }", "}); } }")) == []  # a handler is split (compiler.handlers)
    assert "E601" in codes_of(handler.replace("} } }", "}); } }"), target="original")  # not on the firmware
    leds = " ".join(f"self.setLed({i});" for i in range(19))
    text = (f"role A {{ self.x() > 0; startup s() {{ if (connected_role(UP, A) > 0) {{ {leds} }} }} }}"
            "\ndeployment { A }")
    diagnostics = target_diagnostics(check_text(text).model)
    assert [d.code for d in diagnostics] == ["W601"]
    assert text[diagnostics[0].span.start:].startswith("if (connected_role")


def test_large_if_on_a_stable_condition_is_split():
    leds = " ".join(f"self.setLed({i});" for i in range(40))
    text = f"role A {{ self.x() > 0; startup s() {{ if (self.y() > 0) {{ {leds} }} }} }}\ndeployment {{ A }}"
    assert codes_of(text) == []


def test_long_startup_is_split_into_fragments_under_budget():
    leds = " ".join(f"self.setLed({i});" for i in range(40))
    text = f"role A {{ self.x() > 0; startup s() {{ {leds} }} }}\ndeployment {{ A }}"
    assert codes_of(text) == []


def test_non_constant_argument():
    # every number may be known only at run time (issue 25): the firmware says why it cannot (E605)
    text = "role A { self.x() > 0; startup s() { self.sleepWhileTurning(self.y()); } }\ndeployment { A }"
    assert codes_of(text) == []
    command = "role A { self.x() > 0; command c(n) { self.sleepWhileTurning(n); } }\ndeployment { A }"
    assert codes_of(command, target="original") == ["E605"]
    # the LEDs take a value known only at run time (SET_LED_STACK), except on the firmware
    text = "role A { self.x() > 0; startup s() { self.setLed(self.y()); } }\ndeployment { A }"
    assert codes_of(text) == []


def test_examples_have_no_target_diagnostics(obstacle_text):
    assert codes_of(obstacle_text) == []


def test_mixin_startup_is_reported_as_not_compiled():
    text = "role W { self.y() > 0; }\nrole M modifies W { startup s() { self.sleep(); } }\ndeployment { W }"
    assert "W603" in codes_of(text)
