from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from debug.expr import ExprError, parse

NAMES = {"module": 3, "role": "LeftWheel", "led": 0, "x": None}


@pytest.mark.parametrize(("text", "value"), [
    ("module == 3", True), ('role == "LeftWheel"', True), ("module == 3 and role != 'Axle'", True),
    ("not (module > 2) or led == 0", True), ("-module < 0", True), ("x == none", True), ("module", 3),
    ("module >= 4 || led == 1", False),
])
def test_values(text: str, value: object) -> None:
    assert parse(text).evaluate(NAMES) == value


@pytest.mark.parametrize("text", ["__import__('os')", "module.__class__", "open('f')", "module ==", "1 2",
                                  "", "[1]", "role + 1", "unknown == 1", "'a' < 1", "-role"])
def test_refused(text: str) -> None:
    with pytest.raises(ExprError):
        parse(text).evaluate(NAMES)


@given(st.text(max_size=60))
def test_any_text_is_a_value_or_an_expr_error(text: str) -> None:
    try:
        parse(text).evaluate(NAMES)
    except ExprError:
        pass
