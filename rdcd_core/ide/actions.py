"""Code actions: the fixes attached to the diagnostics that touch the requested range."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.diagnostics import Diagnostic, Fix, TextEdit
from rdcd_core.ide.analysis import Analysis
from rdcd_core.source import Span, newline_of, normalize_newlines


@dataclass(frozen=True)
class CodeAction:
    title: str
    fix: Fix
    diagnostic: Diagnostic
    preferred: bool


def code_actions(analysis: Analysis, span: Span) -> list[CodeAction]:
    actions = []
    newline = newline_of(analysis.text)
    for diagnostic in analysis.diagnostics:
        if diagnostic.span.end < span.start or diagnostic.span.start > span.end:
            continue
        only = len(diagnostic.fixes) == 1
        for fix in diagnostic.fixes:
            actions.append(CodeAction(fix.title, _in_style(fix, newline), diagnostic, only))
    return actions


def _in_style(fix: Fix, newline: str) -> Fix:
    """The fix with its line breaks written as the text writes them (a CRLF file stays CRLF)."""
    if newline == "\n" or not any("\n" in edit.new_text for edit in fix.edits):
        return fix
    return Fix(fix.title, tuple(TextEdit(e.span, normalize_newlines(e.new_text, newline)) for e in fix.edits))
