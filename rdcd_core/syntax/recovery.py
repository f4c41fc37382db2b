"""Error recovery for the LALR driver: report the error, repair, carry on.

At an unexpected token the parser tries small repairs: inserting one or two tokens (';' ')'
'}' …), deleting up to three tokens, or dropping the last shifted punctuation token. Each
candidate is tried by simulating the LALR automaton on the next tokens, and the one that lets
the parser get furthest wins (Burke-Fisher style), if it gets far enough. Otherwise panic mode:
skip to a token where a role, member or statement can start or end, and cut the stack back to
the innermost point that accepts it, so that everything before the broken construct is kept.

A new error is reported only after three tokens have been shifted since the last one, so that
one mistake gives one diagnostic; the message depends on the repair ("expected ';' after the
invariant") and on what the parser was in the middle of (context.py).
"""

from __future__ import annotations

import bisect

from lark import Tree

from rdcd_core.diagnostics import Diagnostic, Fix, TextEdit, make
from rdcd_core.source import LineIndex, Span
from rdcd_core.syntax import ast, messages
from rdcd_core.syntax import automaton as lr
from rdcd_core.syntax import context as ctx
from rdcd_core.syntax.codes import E_MISSING_SEMICOLON
from rdcd_core.syntax.lexer import Tok
from rdcd_core.syntax.messages import TEXT, Message
from rdcd_core.syntax.tables import Tables

_SINGLE = ("COMMA", "SEMI", "RPAR", "RBRACE", "LBRACE", "ASSIGN")  # on a tie, the first wins
_DOUBLE = (("RPAR", "SEMI"), ("SEMI", "RBRACE"), ("RPAR", "RPAR"), ("RBRACE", "RBRACE"), ("LPAR", "RPAR"))
# what a mistyped character (a BAD token of the lexer) may have meant
_REPLACEMENTS = {"=": ("ASSIGN", "EQ"), ":": ("ASSIGN",), "&": ("AND",), "|": ("OR",)}
_STRONG = frozenset({"ROLE", "ABSTRACT", "DEPLOYMENT", "CONSTANT", "STARTUP", "BEHAVIOR", "COMMAND",
                     "IF", "RBRACE"})
_TOP = frozenset({"ROLE", "DEPLOYMENT"})  # roles do not nest: these are resume points at any depth
# what may close the constructs left open when panic mode resumes (';' = an empty if-body)
_CLOSERS = ((), ("SEMI",), ("RBRACE",), ("SEMI", "RBRACE"), ("RBRACE", "RBRACE"), ("RBRACE",) * 3)
_BOUNDARY = frozenset({"SEMI", "LBRACE", "RBRACE"})
_FINISHED = _BOUNDARY  # a line ending in one of these is complete: an error on the next is the next's
_NO_SKIP = _STRONG | {"LBRACE", "$END", "SEMI"}
_LOOKAHEAD = 3  # tokens to shift after an error before the next one is reported
_WINDOW = 10  # tokens a candidate repair is tried on
_REPAIR_MIN = 8  # a repair must let the parser go on this far (or past a ';', '{', '}')
_ELSE_AFTER_ERROR = 40  # an 'else' this many tokens after an error is taken as its follow-on


class Recovery:
    """The error state of one parse; ``recover`` is called by the driver at each error."""

    def __init__(self, t: Tables, text: str, tokens: list[Tok], after_error: set[int]) -> None:
        self.t = t
        self.text = text
        self.tokens = tokens
        self.after_error = after_error  # tokens right after a dropped bad character
        self.eof_offset = len(text)
        self.diagnostics: list[Diagnostic] = []
        self.shifted = _LOOKAHEAD  # real tokens shifted since the last error
        self.saved_deployment: ast.Deployment | None = None
        self.reported_eof = False
        self.brace_debt = 0  # '}' found to be one too many, whose partner is still ahead
        self.attempts: dict[int, int] = {}
        self.last_error: int | None = None  # token index of the last error
        self.previous_error: int | None = None
        self.completed_at: int | None = None  # where tokens were added at the end of the file
        self._lines: LineIndex | None = None
        self._starts: list[int] | None = None

    # ------------------------------------------------------------------ the entry point

    def recover(self, stack: list, values: list, i: int, tok: Tok) -> tuple[int, list[Tok]]:
        """Handles an error at ``tok`` (tokens[i] or the end): returns where to go on, and the
        tokens to feed before it."""
        report = self.shifted >= _LOOKAHEAD and i not in self.after_error
        self.shifted = 0
        self.previous_error, self.last_error = self.last_error, i
        tries = self.attempts[i] = self.attempts.get(i, 0) + 1
        if tok.type != "$END" and lr.reduce_deployment(self.t, stack, values):
            self.saved_deployment = values.pop()
            stack.pop()
            self._report(report, i, messages.after_deployment(tok))
            report = False
        if tok.type == "$END":
            if tries > 4:  # a safety net: the start state always accepts the end
                del stack[1:]
                values.clear()
            else:
                self._complete_at_eof(stack, values, report)
            return i, []
        if tries > 4:  # a safety net: never loop on one token
            return i + 1, []
        if tok.type == "RBRACE" and self.brace_debt and ctx.open_bracket(values) < 0:
            self.brace_debt -= 1
            return i + 1, []
        if tok.type == "ELSE" and not lr.accepts(self.t, stack, ["SEMI", *self._types(i, 2)]):
            return self._stray_else(stack, values, i, tok, report)
        if tok.type == "BAD":  # already reported by the lexer
            return self._replace_bad(stack, i, tok)
        return self._repair(stack, values, i, tok, report)

    def _replace_bad(self, stack: list, i: int, tok: Tok) -> tuple[int, list[Tok]]:
        self.shifted = _LOOKAHEAD  # the lexer's diagnostic covers this token
        ahead = self._types(i + 1, _LOOKAHEAD - 1)
        for cand in _REPLACEMENTS.get(tok.value, ()):
            if lr.accepts(self.t, stack, [cand, *ahead]):
                return i + 1, [Tok(cand, TEXT[cand], tok.start, tok.end)]
        return i + 1, []

    # ------------------------------------------------------------------ repairs

    def _repair(self, stack: list, values: list, i: int, tok: Tok, report: bool) -> tuple[int, list[Tok]]:
        """Applies the small repair after which the parser gets furthest (Burke-Fisher style)."""
        k = ctx.open_bracket(values)
        if k >= 1 and values[k].type == "LBRACE" and ctx.brace_owner(values, k) == "the deployment":
            if tok.type == "NAME" and ctx.is_tok(values[-1], ("NAME",)):
                self._report(report, i, messages.inserted(values, tok, ("COMMA",), self._line, self._prev(i)))
            else:
                self._report_unexpected(report, stack, values, i)
            return self._salvage_deployment(stack, values, i, k)
        best = self._best_repair(stack, values, i)
        if best is None:
            self._report_unexpected(report, stack, values, i)
            return self._panic(stack, values, i)
        kind, arg = best
        if kind == "rewind":
            return self._rewind(stack, values, i, report, *arg)
        if kind == "insert":
            self._report(report, i, messages.inserted(values, tok, arg, self._line, self._prev(i)))
            return i, [self._virtual(cand, i) for cand in arg]
        self._report_unexpected(report, stack, values, i)
        if kind == "delete":
            return i + arg, []
        stack.pop()  # "pop": the last token read goes
        values.pop()
        return i, []

    def _best_repair(self, stack: list, values: list, i: int) -> tuple[str, object] | None:
        window = self._types(i, _WINDOW)
        best: tuple[float, str, object] = (-99, "", None)

        def consider(sequence: list[str], inserted: int, cost: float, kind: str, arg: object,
                     limit: int | None = None, reread: int = 0) -> None:
            """``cost`` tokens changed; then ``sequence`` (``inserted`` made-up tokens, then ``reread``
            tokens read again, then the rest) must parse far enough."""
            nonlocal best
            parsed = lr.progress(self.t, stack, sequence, limit) - inserted - reread
            possible = len(sequence) - inserted - reread - (sequence[-1] == "$END")  # a missing end is E006
            enough = parsed >= min(_REPAIR_MIN, possible) or (
                parsed >= _LOOKAHEAD and _BOUNDARY.intersection(sequence[inserted:inserted + parsed]))
            if enough and parsed >= 1 and parsed - cost > best[0]:
                best = (parsed - cost, kind, arg)

        consider(self._types(i + 1, _WINDOW), 0, 2, "delete", 1)
        body_first = ctx.concrete_method_header(values)
        for cand in _SINGLE:
            cost = 0.5 if cand == "LBRACE" and body_first else 1  # a body rather than ';'
            consider([cand, *window], 1, cost, "insert", (cand,))
        for skip in (2, 3):
            if window[skip - 1] in _NO_SKIP:
                break  # never swallow a structure's brace or keyword to mend a small mistake
            consider(self._types(i + skip, _WINDOW), 0, skip + 1, "delete", skip)
        for pair in _DOUBLE:
            consider([*pair, *window], 2, 2, "insert", pair)
        if values and isinstance(values[-1], Tok) and values[-1].type != "LBRACE":
            consider(window, 0, 2, "pop", None, len(stack) - 1)
        rewind = self._rewind_point(stack, values, i)
        if rewind is not None:  # a block left open: what follows are members, not statements
            depth, j = rewind
            consider(["RBRACE", *self._types(j, _WINDOW + i - j)], 1, 2, "rewind", rewind, depth + 1, i - j)
        return (best[1], best[2]) if best[1] else None

    def _rewind_point(self, stack: list, values: list, i: int) -> tuple[int, int] | None:
        """(stack depth, token index) of the start of the statement being parsed, if any."""
        depth = len(stack) - 1
        while depth > 0 and stack[depth] not in self.t.sync_states:
            depth -= 1
        if depth == 0 or "statement" not in self.t.states[stack[depth]] or depth >= len(stack) - 1:
            return None
        start = ctx.start_of(values[depth])
        if start is None:
            return None
        if self._starts is None:
            self._starts = [tok.start for tok in self.tokens]
        j = bisect.bisect_left(self._starts, start)
        return (depth, j) if j < i else None

    def _rewind(self, stack: list, values: list, i: int, report: bool, depth: int,
                j: int) -> tuple[int, list[Tok]]:
        """Closes the block before the statement that starts at token ``j`` and reads on from there."""
        message = messages.unclosed_block(values, depth, self.tokens[j], self.tokens[i], self._line)
        if message is not None:
            self._report(report, j, message)
        del stack[depth + 1:]
        del values[depth:]
        return j, [self._virtual("RBRACE", j)]

    def _salvage_deployment(self, stack: list, values: list, i: int, k: int) -> tuple[int, list[Tok]]:
        """Keeps the role names of a malformed deployment list, up to its '}'."""
        shifted = [x for v in values[k + 1:] for x in (v.children if isinstance(v, Tree) else (v,))]
        names = [ast.Name(v.value, Span(v.start, v.end)) for v in shifted
                 if isinstance(v, Tok) and v.type == "NAME"]
        tokens = self.tokens
        j = i
        end = tokens[i - 1].end
        while j < len(tokens) and tokens[j].type not in ("RBRACE", "ROLE", "ABSTRACT", "DEPLOYMENT"):
            if tokens[j].type == "NAME":
                names.append(ast.Name(tokens[j].value, Span(tokens[j].start, tokens[j].end)))
            end = tokens[j].end
            j += 1
        if j < len(tokens) and tokens[j].type == "RBRACE":
            end = tokens[j].end
            j += 1
        self.saved_deployment = ast.Deployment(tuple(names), Span(values[k - 1].start, end))
        del stack[k:]
        del values[k - 1:]
        return j, []

    def _panic(self, stack: list, values: list, i: int) -> tuple[int, list[Tok]]:
        """Skips to the first token where a role, member or statement can start or end.

        The stack is cut back to the innermost point (a sync state) that accepts that token,
        possibly after closing the open blocks with '}', so that everything before the broken
        construct is kept.
        """
        levels = [d for d in range(len(stack) - 1, -1, -1) if stack[d] in self.t.sync_states] or [0]
        tokens = self.tokens
        nesting = 0
        for j in range(i, len(tokens)):
            ttype = tokens[j].type
            if ttype in _TOP or (nesting == 0 and (
                    ttype in _STRONG or (j > i and tokens[j - 1].type in ("SEMI", "RBRACE")))):
                ahead = self._types(j, _LOOKAHEAD)
                for depth in levels:
                    for closing in _CLOSERS:
                        if lr.accepts(self.t, stack, [*closing, *ahead], depth + 1):
                            del stack[depth + 1:]
                            del values[depth:]
                            return j, [self._virtual(ttype, j) for ttype in closing]
            if ttype == "LBRACE":
                nesting += 1
            elif ttype == "RBRACE" and nesting > 0:
                nesting -= 1
        del stack[levels[0] + 1:]
        del values[levels[0]:]
        return len(tokens), []

    def _stray_else(self, stack: list, values: list, i: int, tok: Tok, report: bool) -> tuple[int, list[Tok]]:
        prev = self.tokens[i - 1] if i > 0 else None
        if self.previous_error is not None and i - self.previous_error < _ELSE_AFTER_ERROR:
            pass  # most likely its 'if' was lost to the error just before: no new diagnostic
        else:
            if prev is not None and prev.type == "RBRACE":
                self.brace_debt += 1
            self._report(report, i, messages.stray_else(values, prev, self._line))
        j = self._skip_statement(i + 1)
        if j >= len(self.tokens) or lr.accepts(self.t, stack, self._types(j, 1)):
            return j, []
        return self._panic(stack, values, j)

    def _complete_at_eof(self, stack: list, values: list, report: bool) -> None:
        """Closes whatever is open at the end of the file, dropping incomplete pieces."""
        expected = lambda: lr.expected(self.t, stack)  # noqa: E731 - only computed if needed
        self._report(report, len(self.tokens), messages.end_of_file(values, expected, self._line))
        self.reported_eof = True
        end = self.tokens[-1].end if self.tokens else 0
        self.completed_at = end
        for _ in range(4 * len(stack) + 20):
            if lr.accepts(self.t, stack, ["$END"]):
                return
            for cand in ("RPAR", "RBRACE", "SEMI"):
                if lr.accepts(self.t, stack, [cand]):
                    lr.feed(self.t, stack, values, Tok(cand, TEXT[cand], end, end))
                    break
            else:
                if len(stack) > 1:
                    stack.pop()
                    values.pop()
        del stack[1:]
        values.clear()

    # ------------------------------------------------------------------ helpers

    def _report_unexpected(self, report: bool, stack: list, values: list, i: int) -> None:
        if report:
            tok = self._tok(i)
            message = messages.unexpected(values, tok, lr.expected(self.t, stack), self._dangling(i))
            self._report(True, i, message)

    def _report(self, report: bool, i: int, message: Message) -> None:
        """Reports ``message`` at tokens[i] (the end of the file if none), or just after the token before
        it if the message says that something is missing there."""
        if not report:
            return
        prev = self._prev(i)
        if message.after_previous and prev is not None:
            span = Span(prev.end, prev.end)
        else:
            tok = self._tok(i)
            span = Span(tok.start, tok.end)
        fixes = ()
        if message.code == E_MISSING_SEMICOLON and span.start == span.end:
            fixes = (Fix("insert ';'", (TextEdit(span, ";"),)),)
        self.diagnostics.append(make(message.code, span, message.text, related=message.related, fixes=fixes))

    def _tok(self, i: int) -> Tok:
        """tokens[i], or the end of the file."""
        if i < len(self.tokens):
            return self.tokens[i]
        return Tok("$END", "", self.eof_offset, self.eof_offset)

    def _prev(self, i: int) -> Tok | None:
        return self.tokens[i - 1] if 0 < i <= len(self.tokens) else None

    def _dangling(self, i: int) -> Tok | None:
        """The token before tokens[i] if it ends an earlier line in the middle of a construct: then what
        the parser expected is missing at the end of that line (tokens[i] is not the one to blame)."""
        prev = self._prev(i)
        if prev is None or i >= len(self.tokens) or prev.type in _FINISHED:
            return None
        return prev if self._line(prev.end) < self._line(self.tokens[i].start) else None

    def _line(self, offset: int) -> int:
        if self._lines is None:
            self._lines = LineIndex(self.text)
        return self._lines.line_col(offset).line + 1

    def _types(self, i: int, count: int) -> list[str]:
        """The types of ``count`` tokens from ``i`` on, ending with "$END" if the text ends first."""
        result = [tok.type for tok in self.tokens[i:i + count]]
        if len(result) < count:
            result.append("$END")
        return result

    def _virtual(self, ttype: str, i: int) -> Tok:
        """A made-up token, placed (zero-width) right after the token before ``i``."""
        at = self.tokens[i - 1].end if i > 0 else 0
        return Tok(ttype, TEXT[ttype], at, at)

    def _skip_statement(self, j: int) -> int:
        """The index after the statement starting at ``j`` (the body of a stray 'else')."""
        tokens = self.tokens
        nesting = 0
        while j < len(tokens):
            ttype = tokens[j].type
            if ttype in ("LBRACE", "LPAR"):
                nesting += 1
            elif ttype in ("RBRACE", "RPAR"):
                if nesting == 0:
                    return j
                nesting -= 1
                if nesting == 0 and ttype == "RBRACE" and not self._is(j + 1, "ELSE"):
                    return j + 1
            elif ttype == "SEMI" and nesting == 0 and not self._is(j + 1, "ELSE"):
                return j + 1
            j += 1
        return j

    def _is(self, j: int, ttype: str) -> bool:
        return j < len(self.tokens) and self.tokens[j].type == ttype
