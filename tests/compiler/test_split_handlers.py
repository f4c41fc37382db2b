"""Event handlers too large for a fragment (rdcd_core/compiler/handlers.py): the handler keeps the
statements that fit and goes on in commands (CONTINUE_COMMAND), in the same run; it ends as the
unsplit handler does in the lattice world, without loss and at 10 % loss."""

from __future__ import annotations

import pytest

from rdcd_core.frontend import check_text
from tests.compiler.split_run import both, same_outcome

BODY = ("self.disableEvent(EVENT_PROXIMITY_0); hits := hits + 1; self.setLed(1); self.turnTowards(30); "
        "self.sleep(); self.setLed(2); self.turnTowards(-30); self.sleep(); self.setLed(3); "
        "self.turnTowards(0); self.sleep(); self.setLed(hits + 4); self.turnTowards(60); self.sleep();")


def program(body: str = BODY) -> str:
    return ("state hits := 0;\nrole Wheel { self.center_position == EAST_WEST;\n"
            f"  startup s() {{ self.handleEvent(EVENT_PROXIMITY_0, {{ {body} }}); }}\n}}\n"
            "deployment { Wheel }\n")


def over(result) -> list:
    return [d for d in result.diagnostics if d.code in ("W601", "E601")]


def test_a_large_handler_fits_and_goes_on_in_a_command():
    split, unsplit = both(program())
    assert [f.size for f in unsplit.fragments] == [46]
    assert all(f.size <= split.program_budget for f in split.fragments) and not split.diagnostics
    listing = b"".join(f.code for f in split.fragments)
    assert bytes([79]) in listing  # CONTINUE_COMMAND


@pytest.mark.parametrize("loss,seed", [(0.0, 5), (0.1, 1), (0.1, 3)])
def test_the_split_handler_ends_as_the_unsplit_one(loss, seed):
    after, before = same_outcome(program(), seconds=20.0, loss=loss, seed=seed, obstacles=True)
    assert after == before
    wheels = [m for m, (role, *_) in after.items() if role == "Wheel"]
    assert wheels and all(after[m][2] == 5 and after[m][3] == 60 for m in wheels)  # the last statements ran


def test_a_handler_that_fits_keeps_its_bytes():
    small = program("self.setLed(1); self.sleep(); self.setLed(0);")
    split, unsplit = both(small)
    assert [f.code for f in split.fragments] == [f.code for f in unsplit.fragments]


def test_not_split_on_the_original_target():
    leds = " ".join(f"self.setLed({i}); self.sleep();" for i in range(12))
    text = program(leds).replace("state hits := 0;\n", "")
    result = check_text(text, target="original")
    assert not result.has_errors or over(result)
    assert [d.code for d in over(result)] in (["W601"], ["E601"])
    assert [d.code for d in over(check_text(text))] == []


def test_a_huge_handler_is_split_or_reported_never_a_traceback():
    leds = " ".join(f"self.setLed({i % 100}); self.sleep();" for i in range(200))
    result = check_text(program(leds))
    assert not any(d.code.startswith("E9") for d in result.diagnostics)
    assert over(result)  # 400 statements need more command numbers than the table has: reported


def test_a_handler_as_large_as_the_numbers_allow_fits():
    leds = " ".join(f"self.setLed({i}); self.sleep();" for i in range(30))
    result = check_text(program(leds))
    assert not over(result) and all(f.size <= 43 for f in result.compiled.fragments)


def test_one_deeply_nested_statement_is_named():
    nested = "if (hits > 0) " * 12 + "{ " + " ".join(f"self.setLed({i});" for i in range(30)) + " }"
    text = program(f"self.setLed(1); {nested}")
    result = check_text(text)
    assert not any(d.code.startswith("E9") for d in result.diagnostics)
    for d in over(result):
        assert text[d.span.start:].startswith("if (hits > 0)")
