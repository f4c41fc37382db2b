"""Applying a diagnostic's fix to a text, for tests that check the fixed program."""

from __future__ import annotations

from rdcd_core.diagnostics import Fix


def apply_fix(text: str, fix: Fix) -> str:
    for edit in sorted(fix.edits, key=lambda e: e.span.start, reverse=True):
        text = text[:edit.span.start] + edit.new_text + text[edit.span.end:]
    return text
