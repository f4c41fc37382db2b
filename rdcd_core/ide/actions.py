"""Code actions: the fixes attached to the diagnostics that touch the requested range, and the
editor's own: declaring a state that an assignment names but nothing declares (E702)."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.diagnostics import Diagnostic, Fix, TextEdit
from rdcd_core.ide.analysis import Analysis
from rdcd_core.semantics.codes import UNKNOWN_STATE
from rdcd_core.source import Span, newline_of, normalize_newlines
from rdcd_core.syntax import ast


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
        if diagnostic.code == UNKNOWN_STATE:
            for fix in declare_state_fixes(analysis, diagnostic):
                actions.append(CodeAction(fix.title, _in_style(fix, newline), diagnostic, False))
    return actions


def declare_state_fixes(analysis: Analysis, diagnostic: Diagnostic) -> list[Fix]:
    """For ``s := …`` where no state ``s`` exists: declare it as module state (beside the other
    module states, else before the first role) or as role state of the role around it."""
    program, text = analysis.program, analysis.text
    name = text[diagnostic.span.start:diagnostic.span.end]
    if program is None or not name.isidentifier():
        return []
    fixes = []
    if program.states:
        at, new_text = program.states[-1].span.end, f"\nstate {name} := 0;"
    else:
        first = min([r.span.start for r in program.roles] + [len(text)])
        at = text.rfind("\n", 0, first) + 1
        new_text = f"state {name} := 0;\n\n"
    fixes.append(Fix(f"declare module state '{name}'", (TextEdit(Span(at, at), new_text),)))
    role = next((r for r in program.roles if r.span.start <= diagnostic.span.start < r.span.end), None)
    if role is not None and role.modifies is None and role.name.text:
        at = role.header_span.end
        fixes.append(Fix(f"declare role state '{name}' in '{role.name.text}'",
                         (TextEdit(Span(at, at), f"\n{_member_indent(text, role)}state {name} := 0;"),)))
    return fixes


def _member_indent(text: str, role: ast.RoleDecl) -> str:
    """The indentation of the role's first member, or two spaces."""
    if role.members:
        start = role.members[0].span.start
        line_start = text.rfind("\n", 0, start) + 1
        if line_start > role.header_span.end and not text[line_start:start].strip():
            return text[line_start:start]
    return "  "


def _in_style(fix: Fix, newline: str) -> Fix:
    """The fix with its line breaks written as the text writes them (a CRLF file stays CRLF)."""
    if newline == "\n" or not any("\n" in edit.new_text for edit in fix.edits):
        return fix
    return Fix(fix.title, tuple(TextEdit(e.span, normalize_newlines(e.new_text, newline)) for e in fix.edits))
