"""docs/diagnostics.md lists every code and is up to date with the code tables."""

from __future__ import annotations

from rdcd_core.diagnostics import all_codes
from rdcd_core.diagnostics_doc import RETIRED, render
from tests.conftest import ROOT


def test_diagnostics_doc_is_up_to_date() -> None:
    current = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    assert current == render(), \
        "docs/diagnostics.md is stale: run 'python -m rdcd_core.diagnostics_doc > docs/diagnostics.md'"


def test_every_code_is_documented() -> None:
    text = render()
    for info in all_codes():
        assert f"### {info.code}" in text


def test_retired_codes_are_documented_and_never_reused() -> None:
    text = render()
    registered = {info.code for info in all_codes()}
    for code in RETIRED:
        assert code not in registered, code
        assert f"### {code}" in text and "**retired**" in text.split(f"### {code}")[1].split("###")[0]
