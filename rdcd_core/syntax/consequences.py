"""One error per mistake: the checker's diagnostics that only follow from a syntax error.

Recovery repairs a broken statement so that the rest of the program can be checked: it drops a
bad character (``speed # side`` becomes ``speed side``), inserts a missing token or skips to the
next ``;``. The repaired statement is not what was written, so what the checker finds wrong in it
(``'turnContinuously' takes 1 argument, not 2``) is a consequence of the syntax error, not a
second mistake. Such diagnostics are dropped: those whose range overlaps the innermost statement or
member around a syntax error (for an ``if``, only its header: its branches are checked as usual).

Two more kinds of consequence. Recovery may drop a declaration (``constant # := EAST;``), and then
every use of it is "unknown" or "not defined": when a syntax error lies where recovery dropped a
member (outside the members that survived and the method bodies), the checker's diagnostics of
something missing (``MISSING``; of a missing role only for an error outside every role's members)
are dropped in the whole program, as they may all be consequences; with any syntax error, "never
used/read" warnings are dropped (a use may have been lost). And within one statement or member
only the first syntax error is kept: a bad character that replaced a ``)`` is one mistake, not
also a missing ``)`` at the ``;``.
"""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.source import Span
from rdcd_core.syntax import ast

# members and statements whose text a repair changes as a whole
_WHOLE = (ast.CallStmt, ast.AssignStmt, ast.EmptyStmt, ast.ConstantDef, ast.StateDecl, ast.Invariant,
          ast.AbstractConstants)


# the checker's diagnostics of something missing or unknown: a lost declaration causes them
MISSING = frozenset({"E102", "E105", "E110", "E201", "E208", "E301", "E306", "E307", "E309", "E501",
                     "E701", "E702", "E703", "E706"})
UNUSED = frozenset({"W504", "W702"})  # a lost use causes them


ROLE_LEVEL = frozenset({"E102", "E105", "E208", "E501"})  # a lost role declaration causes them


def lost_declarations(program: ast.Program, errors: list[diag.Diagnostic]) -> frozenset[str]:
    """The codes of ``MISSING`` that may follow from a declaration recovery dropped: a syntax error
    outside every member that survived (a member's own error leaves the member declared) and
    outside method bodies; role-level codes only for one outside every role's members."""
    members = [m.span for role in program.roles for m in role.members]
    bodies = [node.body.span for node in ast.walk(program)
              if isinstance(node, ast.MethodDecl) and node.body is not None]
    drop: frozenset[str] = frozenset()
    for error in errors:
        at = error.span.start
        if any(s.start <= at < s.end for s in members) or any(b.start <= at < b.end for b in bodies):
            continue
        in_role = any(r.header_span.end <= at < r.span.end for r in program.roles)
        drop |= MISSING - ROLE_LEVEL if in_role else MISSING
    return drop


def first_per_range(syntax: list[diag.Diagnostic], ranges: list[Span | None]) -> list[diag.Diagnostic]:
    """The syntax diagnostics less every error after the first in one statement or member
    (``ranges``: the range around each diagnostic of ``syntax``, None when it has none)."""
    seen: set[Span] = set()
    kept = []
    for d, r in zip(syntax, ranges, strict=True):
        if r is not None and d.severity is diag.Severity.ERROR:
            if r in seen:
                continue
            seen.add(r)
        kept.append(d)
    return kept


def broken_ranges(program: ast.Program, errors: list[diag.Diagnostic]) -> list[Span | None]:
    """For each syntax error, the innermost statement or member (an ``if``'s header) around it
    (None: none)."""
    if not errors:
        return []
    candidates: list[Span] = []
    for node in ast.walk(program):
        if isinstance(node, _WHOLE):
            candidates.append(node.span)
        elif isinstance(node, ast.IfStmt):
            body = getattr(node.then_body, "span", None)
            candidates.append(Span(node.span.start, body.start if body is not None else node.span.end))
        elif isinstance(node, ast.MethodDecl) and node.body is not None:
            candidates.append(Span(node.span.start, node.body.span.start))  # its header
    ranges: list[Span | None] = []
    for error in errors:
        at = error.span.start
        around = [s for s in candidates if s.start <= at < s.end or (s.start < at == s.end)]
        ranges.append(min(around, key=lambda s: s.end - s.start) if around else None)
    return ranges


def without_consequences(found: list[diag.Diagnostic], ranges: list[Span | None],
                         drop: frozenset[str] = frozenset()) -> list[diag.Diagnostic]:
    """``found`` less the diagnostics whose range overlaps one of ``ranges`` and those whose
    code is in ``drop``."""
    spans = [r for r in ranges if r is not None]
    if not spans and not drop:
        return found
    return [d for d in found if d.code not in drop
            and not any(d.span.start < r.end and r.start < max(d.span.end, d.span.start + 1) for r in spans)]


def one_error_per_mistake(program: ast.Program, syntax: list[diag.Diagnostic],
                          checker: list[diag.Diagnostic]) -> list[diag.Diagnostic]:
    """The syntax and checker diagnostics to report: the consequences of syntax errors dropped."""
    errors = [d for d in syntax if d.severity is diag.Severity.ERROR]
    if not errors:
        return [*syntax, *checker]
    ranges = broken_ranges(program, syntax)
    drop = UNUSED | lost_declarations(program, errors)
    return [*first_per_range(syntax, ranges), *without_consequences(checker, ranges, drop)]
