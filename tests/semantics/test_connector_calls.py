"""The connector and joint calls: constant connectors that can never latch (E220), actions only
where they run exactly once (E320), E605 on the original target for each of them."""

from __future__ import annotations

import pytest

from rdcd_core.frontend import check_text


def codes_of(text: str, target: str = "default") -> list[str]:
    return [d.code for d in check_text(text, target=target).diagnostics]


def program(body: str, invariant: str = "") -> str:
    return f"role A {{ {invariant} startup s() {{ {body} }} }}\ndeployment {{ A }}"


@pytest.mark.parametrize("call", ["self.connect(1)", "self.disconnect(7)", "self.connect(8)",
                                  "self.isConnected(-1)", "self.isAligned(9)", "self.connect(2 + 1)"])
def test_a_connector_that_can_never_latch_is_e220(call: str) -> None:
    assert "E220" in codes_of(program(f"if ({call}) {{ self.sleep(); }}"))


@pytest.mark.parametrize("call", ["self.connect(0)", "self.disconnect(6)", "self.isConnected(3)",
                                  "self.isAligned(7)", "self.turnQuarters(-2)"])
def test_good_calls_are_clean_and_e605_on_the_original_target(call: str) -> None:
    action = "Connected" not in call and "Aligned" not in call
    text = program((f"{call}; " if action else "") + f"if (!{call}) {{ self.sleep(); }}")
    assert codes_of(text) == []
    assert codes_of(text, "original").count("E605") == (2 if action else 1)


@pytest.mark.parametrize("text", [
    program("self.sleep();", "self.connect(0);"),  # an invariant: evaluated by every discovery
    program("if (self.connect(0) == self.connect(2)) { self.sleep(); }"),  # operands run twice
    program("self.setLed(self.turnQuarters(1));"),
])
def test_an_action_inside_an_expression_is_e320(text: str) -> None:
    assert "E320" in codes_of(text)


def test_an_action_as_a_statement_has_no_unused_value_warning() -> None:
    assert codes_of(program("self.turnQuarters(1);")) == []
