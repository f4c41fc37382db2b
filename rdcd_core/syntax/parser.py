"""``parse(text)``: RDCD text to an AST (always a ``Program``) plus syntax diagnostics.

The LALR(1) table and the AST callbacks come from Lark (grammar.lark, builder.py); this module
drives them token by token so that it can recover from errors (recovery.py) and report every
independent syntax error of a file. Nothing here raises on user input.
"""

from __future__ import annotations

import gc
from dataclasses import dataclass, field, replace

from rdcd_core.diagnostics import Diagnostic, make
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.syntax.builder import DEPTHS, MAX_DEPTH
from rdcd_core.syntax.codes import E_MISSING_BODY, E_MISSING_DEPLOYMENT, E_TOO_DEEP, E_UNTERMINATED_COMMENT
from rdcd_core.syntax.lexer import Tok
from rdcd_core.syntax.recovery import Recovery
from rdcd_core.syntax.tables import Tables, tables

__all__ = ["ParseResult", "parse"]


@dataclass
class ParseResult:
    program: ast.Program
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.diagnostics


def parse(text: str) -> ParseResult:
    """Parses ``text``; on errors the program holds everything that could be recovered."""
    # The parser allocates many small objects and no cycles: the cyclic GC would only rescan
    # the heap again and again (up to a third of the time on large files).
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        return _parse(text)
    finally:
        if gc_was_enabled:
            gc.enable()


def _parse(text: str) -> ParseResult:
    t = tables()
    lexed = t.lexer.lex(text)
    recovery = Recovery(t, text, lexed.tokens, lexed.after_error)
    too_deep = DEPTHS.reset()
    try:
        roles, deployment = _drive(t, lexed.tokens, recovery)
    finally:
        DEPTHS.reset()
    if too_deep:
        roles = _drop_too_deep(roles, too_deep, recovery.diagnostics)
    if deployment is None:
        deployment = recovery.saved_deployment
    diagnostics = lexed.diagnostics + recovery.diagnostics
    diagnostics.extend(_check_members(roles, recovery.completed_at))
    lex_cut = any(d.code == E_UNTERMINATED_COMMENT for d in lexed.diagnostics)
    cut = lex_cut or (recovery.diagnostics and any(tok.type == "DEPLOYMENT" for tok in lexed.tokens))
    if deployment is None and not recovery.reported_eof and not cut:
        end = len(text)
        diagnostics.append(make(E_MISSING_DEPLOYMENT, Span(end, end),
                                "missing deployment: end the program with 'deployment { RoleA, RoleB }'"))
    diagnostics.sort(key=lambda d: (d.span.start, d.span.end))
    program = ast.Program(roles, deployment, Span(0, len(text)), tuple(lexed.comments))
    return ParseResult(program, diagnostics)


def _drive(t: Tables, tokens: list[Tok], recovery: Recovery) -> tuple:
    """The LALR loop of lark's ParserState.feed_token, inlined, with a hook for recovery."""
    states = t.states
    end_state = t.end_state
    stack = [t.start_state]
    values: list = []
    n = len(tokens)
    eof = Tok("$END", "", recovery.eof_offset, recovery.eof_offset)
    pending: list[Tok] = []  # tokens inserted by the recovery, fed before tokens[i] (last first)
    i = 0
    while True:
        tok = pending[-1] if pending else (tokens[i] if i < n else eof)
        ttype = tok.type
        while True:
            action = states[stack[-1]].get(ttype)
            if action is None:
                break
            is_shift, arg = action
            if is_shift:
                stack.append(arg)
                values.append(tok)
                break
            size, origin, callback = arg
            if callback is None:  # a unit rule: only the state changes
                stack[-1] = states[stack[-2]][origin][1]
                continue
            if size:
                children = values[-size:]
                del stack[-size:]
                del values[-size:]
            else:
                children = []
            values.append(callback(children))
            stack.append(states[stack[-1]][origin][1])
            if ttype == "$END" and stack[-1] == end_state:
                return values[-1]
        if action is not None:  # shifted
            if pending:
                pending.pop()
            else:
                i += 1
                recovery.shifted += 1
            continue
        if pending:  # an inserted token that does not fit after all: drop it
            pending.pop()
            continue
        i, inserted = recovery.recover(stack, values, i, tok)
        pending.extend(reversed(inserted))


def _drop_too_deep(roles: tuple[ast.RoleDecl, ...], too_deep: list, diagnostics: list[Diagnostic]) -> tuple:
    """Drops the members holding a tree deeper than MAX_DEPTH: later passes recurse over trees."""
    spans = [node.span for node in too_deep]
    for span in spans[:20]:
        diagnostics.append(make(E_TOO_DEEP, span, f"this is nested more than {MAX_DEPTH} levels deep: "
                                "split it up (it is left out of the analysis)"))
    result = []
    for role in roles:
        kept = tuple(m for m in role.members
                     if not any(m.span.start <= s.start and s.end <= m.span.end for s in spans))
        result.append(role if len(kept) == len(role.members) else replace(role, members=kept))
    return tuple(result)


def _check_members(roles: tuple[ast.RoleDecl, ...], completed_at: int | None) -> list[Diagnostic]:
    """Body-less methods must be abstract (unless the ';' was made up at the end of the file)."""
    result = []
    for role in roles:
        for member in role.members:
            if (isinstance(member, ast.MethodDecl) and member.body is None and not member.is_abstract
                    and member.span.end != completed_at):
                result.append(make(E_MISSING_BODY, member.name.span,
                                   f"method '{member.name.text}' has no body: add '{{ … }}', "
                                   "or declare it 'abstract'"))
    return result
