"""check_text: syntax + semantic (+ target) diagnostics in one sorted list; never raises."""

from __future__ import annotations

import pytest

from rdcd_core import frontend
from tests.conftest import EXAMPLES


def test_diagnostics_sorted_and_merged() -> None:
    result = frontend.check_text("role A { self.y( > 0; }\nrole A { }\ndeployment { A, B }")
    codes = [d.code for d in result.diagnostics]
    assert any(c.startswith("E0") for c in codes) and "E101" in codes and "E501" in codes
    starts = [d.span.start for d in result.diagnostics]
    assert starts == sorted(starts)


def test_packet_budget_reaches_the_compiler() -> None:
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    assert frontend.check_text(text).diagnostics == []
    small = frontend.check_text(text, packet_budget=12).diagnostics
    assert small and all(d.code.startswith(("E6", "W6")) for d in small)


def test_no_target_checks_when_there_are_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = []
    monkeypatch.setattr(frontend, "_target_diagnostics", lambda *a: calls.append(a) or [])
    frontend.check_text("role A { self.y() > EAST; }\ndeployment { A }")
    assert calls == []
    frontend.check_text("role A { self.y() > 0; }\ndeployment { A }")
    assert len(calls) == 1


def test_internal_errors_become_diagnostics(monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(program):  # type: ignore[no-untyped-def]
        raise RuntimeError("boom")

    monkeypatch.setattr(frontend, "analyze", broken)
    result = frontend.check_text("role A { }\ndeployment { A }")
    assert [d.code for d in result.diagnostics] == ["E100"]
    assert "boom" in result.diagnostics[0].message
    assert result.model.roles == {}


def test_very_long_expressions_are_checked_without_crashing() -> None:
    chain = "+".join(["0"] * 20000)
    result = frontend.check_text(f"role A {{ self.x() == {chain}; }}\ndeployment {{ A }}")
    assert not any("semantic analysis" in d.message for d in result.diagnostics)
