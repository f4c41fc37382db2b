"""Helpers for the semantic tests: check a program text, find diagnostics by code."""

from __future__ import annotations

import pytest

from rdcd_core.diagnostics import Diagnostic
from rdcd_core.frontend import CheckResult, check_text


class Checked:
    def __init__(self, text: str) -> None:
        self.text = text
        self.result: CheckResult = check_text(text)
        self.index = self.result.line_index

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return self.result.diagnostics

    @property
    def model(self):  # type: ignore[no-untyped-def]
        return self.result.model

    def line(self, diagnostic: Diagnostic) -> int:
        return self.index.line_col(diagnostic.span.start).line + 1

    def source(self, diagnostic: Diagnostic) -> str:
        return self.text[diagnostic.span.start:diagnostic.span.end]

    def with_code(self, code: str) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.code == code]

    def codes(self) -> list[str]:
        return [d.code for d in self.diagnostics]

    def summary(self) -> str:
        return "\n".join(f"{self.line(d)}: {d.code} {d.message}" for d in self.diagnostics)


@pytest.fixture
def check():  # type: ignore[no-untyped-def]
    return Checked
