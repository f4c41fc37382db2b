"""``parse(text)``: RDCD text to an AST (always a ``Program``) plus syntax diagnostics.

The LALR(1) table and the AST callbacks come from Lark (grammar.lark, builder.py); this module
drives them token by token so that it can recover from errors (recovery.py) and report every
independent syntax error of a file. Nothing here raises on user input.

An editor re-parses after every edit: given the previous result, the parser takes each role it
finds unchanged at the same offset as it is, instead of lexing and parsing it again.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field, replace

from rdcd_core.diagnostics import Diagnostic, make
from rdcd_core.gcpause import gc_paused
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.syntax.builder import DEPTHS, MAX_DEPTH, MAX_HEIGHT
from rdcd_core.syntax.codes import (
    E_MISSING_BODY,
    E_MISSING_DEPLOYMENT,
    E_TOO_DEEP,
    E_TOO_LONG,
    E_UNTERMINATED_COMMENT,
)
from rdcd_core.syntax.lexer import LexResult, Tok
from rdcd_core.syntax.recovery import Recovery
from rdcd_core.syntax.tables import Tables, tables

__all__ = ["ParseResult", "parse"]


@dataclass
class ParseResult:
    program: ast.Program
    diagnostics: list[Diagnostic] = field(default_factory=list)
    text: str = ""  # the text parsed

    @property
    def ok(self) -> bool:
        return not self.diagnostics


def parse(text: str, previous: ParseResult | None = None) -> ParseResult:
    """Parses ``text``; on errors the program holds everything that could be recovered.

    ``previous``, the result for an earlier version of the text, only makes it faster: the roles it
    has unchanged at the same offset are reused (when it has no diagnostics).
    """
    with gc_paused():
        return _parse(text, previous)


def _parse(text: str, previous: ParseResult | None) -> ParseResult:
    t = tables()
    if previous is not None and previous.ok:
        reuse = _reuse(t, text, previous)
        if reuse is not None:
            lexed, reused = reuse
            driven = _run(t, text, lexed, reused)
            if driven is not None:
                return _result(text, lexed, driven)
    lexed = t.lexer.lex(text)
    driven = _run(t, text, lexed, None)
    assert driven is not None  # only a drive that reuses roles gives up
    return _result(text, lexed, driven)


def _result(text: str, lexed: LexResult, driven: tuple[tuple, Recovery, list]) -> ParseResult:
    (roles, deployment, states, sequences), recovery, (too_deep, too_long) = driven
    if too_deep or too_long:
        roles = _drop_too_deep(roles, too_deep, too_long, recovery.diagnostics)
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
    program = ast.Program(roles, deployment, Span(0, len(text)), tuple(lexed.comments), states,
                          sequences)
    return ParseResult(program, diagnostics, text)


_SPACE = " \t\f\r\n\ufeff"  # grammar.lark's WS


def _reuse(t: Tables, text: str, previous: ParseResult) -> tuple[LexResult, dict[int, ast.RoleDecl]] | None:
    """The tokens of ``text`` where each role of ``previous`` (a parse without diagnostics) found
    unchanged at its offset is one placeholder token (its first), with those roles by the index of
    their placeholder; None if nothing is reused, or if a stretch between them does not lex cleanly.

    Lexing resumes at the end of a role (its '}' ends a token), and a stretch lexed up to a role
    gives the tokens the whole text gives if its last one ends before the role or cannot go on
    (punctuation, a block comment). A role's tree depends only on its tokens, so the driver can
    push it whole where the parser is between roles.
    """
    lexer = t.lexer
    old = previous.text
    old_comments = previous.program.comments
    comment_starts = [comment.span.start for comment in old_comments]
    tokens: list[Tok] = []
    comments: list[ast.Comment] = []
    reused: dict[int, ast.RoleDecl] = {}
    position = 0
    for role in previous.program.roles:
        start, end = role.span.start, role.span.end
        if not text.startswith(old[start:end], start):
            continue
        if text[position:start].strip(_SPACE):
            stretch = lexer.lex(text, position, start)
            if stretch.diagnostics or not _ends_cleanly(stretch, start, lexer.literals):
                return None
            tokens += stretch.tokens
            comments += stretch.comments
        first = "abstract" if text.startswith("abstract", start) else "role"
        reused[len(tokens)] = role
        tokens.append(Tok(lexer.keywords[first], first, start, start + len(first)))
        comments += old_comments[bisect.bisect_left(comment_starts, start):
                                 bisect.bisect_left(comment_starts, end)]
        position = end
    if not reused:
        return None
    rest = lexer.lex(text, position)
    if rest.diagnostics:
        return None
    tokens += rest.tokens
    comments += rest.comments
    return LexResult(tokens, comments, [], set()), reused


def _ends_cleanly(stretch: LexResult, end: int, punctuation: dict[str, str]) -> bool:
    """Whether the last token or comment of ``stretch``, lexed up to ``end``, is the same when the
    text goes on."""
    last_token = stretch.tokens[-1] if stretch.tokens else None
    last_comment = stretch.comments[-1] if stretch.comments else None
    if last_comment is not None and (last_token is None or last_comment.span.start > last_token.start):
        return last_comment.span.end < end or last_comment.text.startswith("/*")
    return last_token is None or last_token.end < end or last_token.value in punctuation


def _run(t: Tables, text: str, lexed: LexResult,
         reused: dict[int, ast.RoleDecl] | None) -> tuple[tuple, Recovery, list] | None:
    """(roles and deployment, the recovery state, (the trees nested too deeply, those too high)) of
    one drive; None if reusing roles met a syntax error."""
    recovery = Recovery(t, text, lexed.tokens, lexed.after_error)
    limits = DEPTHS.reset()
    try:
        driven = _drive(t, lexed.tokens, recovery, reused)
    finally:
        DEPTHS.reset()
    return None if driven is None else (driven, recovery, limits)


def _drive(t: Tables, tokens: list[Tok], recovery: Recovery,
           reused: dict[int, ast.RoleDecl] | None) -> tuple | None:
    """The LALR loop of lark's ParserState.feed_token, inlined, with a hook for recovery.

    With ``reused`` (from ``_reuse``), the role of a placeholder token is pushed whole where the
    parser is between roles, and anything else (a placeholder elsewhere, a syntax error) gives None
    instead of a recovery: the caller then parses the whole text again.
    """
    states = t.states
    role_states = t.role_states
    after_unit_rules = t.after_unit_rules
    end_state = t.end_state
    stack = [t.start_state]
    values: list = []
    n = len(tokens)
    eof = Tok("$END", "", recovery.eof_offset, recovery.eof_offset)
    pending: list[Tok] = []  # tokens inserted by the recovery, fed before tokens[i] (last first)
    i = 0
    shifted = 0  # real tokens shifted since the last call of the recovery (added to its count there)
    while True:
        tok = pending[-1] if pending else (tokens[i] if i < n else eof)
        ttype = tok.type
        while True:
            action = states[stack[-1]].get(ttype)
            if action is None:
                break
            is_shift, arg = action
            if is_shift:
                if reused is not None and i in reused:  # as if the role's tokens were shifted and reduced
                    if stack[-1] not in role_states:
                        return None
                    stack.append(states[stack[-1]]["role"][1])
                    values.append(reused[i])
                else:
                    stack.append(arg)
                    values.append(tok)
                break
            size, origin, callback = arg
            if callback is None:  # a unit rule, and those that follow it: only the state changes
                stack[-1] = after_unit_rules(stack[-2], stack[-1], ttype)
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
                shifted += 1
            continue
        if pending:  # an inserted token that does not fit after all: drop it
            pending.pop()
            continue
        if reused is not None:
            return None
        recovery.shifted += shifted
        shifted = 0
        i, inserted = recovery.recover(stack, values, i, tok)
        pending.extend(reversed(inserted))


def _drop_too_deep(roles: tuple[ast.RoleDecl, ...], too_deep: list, too_long: list,
                   diagnostics: list[Diagnostic]) -> tuple:
    """Drops the members holding a tree nested deeper than MAX_DEPTH or higher than MAX_HEIGHT:
    later passes recurse over trees."""
    found = []  # the outermost of the nodes (too_deep and too_long can hold one inside another)
    nodes = [(node.span, False) for node in too_deep] + [(node.span, True) for node in too_long]
    for span, long in sorted(nodes, key=lambda item: (item[0].start, -item[0].end)):
        if not found or span.end > found[-1][0].end:
            found.append((span, long))
    for span, long in found[:20]:
        if long:
            message = (f"this has more than {MAX_HEIGHT} operations one inside another (each operator of "
                       "'a + b + c' and each 'else if' counts), more than rdcd takes: split it into "
                       "constants or methods (it is left out of the analysis)")
            diagnostics.append(make(E_TOO_LONG, span, message))
        else:
            diagnostics.append(make(E_TOO_DEEP, span, f"this is nested more than {MAX_DEPTH} levels deep: "
                                    "split it up (it is left out of the analysis)"))
    spans = [span for span, _ in found]
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
