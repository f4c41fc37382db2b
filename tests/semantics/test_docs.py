"""docs/diagnostics.md lists every code and is up to date with the code tables."""

from __future__ import annotations

from rdcd_core.diagnostics import all_codes
from rdcd_core.diagnostics_doc import render
from tests.conftest import ROOT


def test_diagnostics_doc_is_up_to_date() -> None:
    current = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    assert current == render(), \
        "docs/diagnostics.md is stale: run 'python -m rdcd_core.diagnostics_doc > docs/diagnostics.md'"


def test_every_code_is_documented() -> None:
    text = render()
    for info in all_codes():
        assert f"### {info.code}" in text
