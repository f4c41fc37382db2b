"""Code actions: the fixes attached to the diagnostics that touch the requested range."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.diagnostics import Diagnostic, Fix
from rdcd_core.ide.analysis import Analysis
from rdcd_core.source import Span


@dataclass(frozen=True)
class CodeAction:
    title: str
    fix: Fix
    diagnostic: Diagnostic
    preferred: bool


def code_actions(analysis: Analysis, span: Span) -> list[CodeAction]:
    actions = []
    for diagnostic in analysis.diagnostics:
        if diagnostic.span.end < span.start or diagnostic.span.start > span.end:
            continue
        only = len(diagnostic.fixes) == 1
        for fix in diagnostic.fixes:
            actions.append(CodeAction(fix.title, fix, diagnostic, only))
    return actions
