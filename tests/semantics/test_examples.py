"""The shipped examples check clean; the verbatim Figure 5 gives one syntax error and no more."""

from __future__ import annotations

import pytest

from tests.conftest import EXAMPLES


@pytest.mark.parametrize("name", ["obstacle_avoidance.rdcd", "snake_wave.rdcd"])
def test_example_is_clean(check, name: str) -> None:
    checked = check((EXAMPLES / name).read_text(encoding="utf-8"))
    assert checked.diagnostics == [], checked.summary()


def test_figure5_verbatim_has_only_the_brace_error(check) -> None:
    checked = check((EXAMPLES / "figure5_verbatim.rdcd").read_text(encoding="utf-8"))
    assert [d.code[:2] for d in checked.diagnostics] == ["E0"], checked.summary()
    assert set(checked.model.deployment) == {"RightWheel", "LeftWheel", "Axle"}
