"""The RDCD lexer, derived from the terminals of grammar.lark.

One regular expression, built from the grammar's terminal definitions, splits the text into
(white space, token) pairs in a single ``findall``; keywords and punctuation are looked up in a
table, names and numbers told by their first character. Comments are kept (for
``Program.comments``).
Bad characters and an unterminated ``/*`` become diagnostics: the lexer never raises.

Lines are the LSP's (``rdcd_core.source``): a line comment ends at ``\\n`` or ``\\r`` (so at
``\\r\\n`` too) and nowhere else; form feed is white space inside a line, and vertical tab, U+0085,
U+2028, U+2029 and the other characters ``str.splitlines`` breaks at are bad characters outside
comments and ordinary ones inside them (grammar.lark's LINE_COMMENT, BLOCK_COMMENT and WS).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from rdcd_core.diagnostics import Diagnostic, make
from rdcd_core.source import Span
from rdcd_core.syntax.ast import Comment
from rdcd_core.syntax.codes import E_BAD_CHARACTER, E_UNTERMINATED_COMMENT


class Tok:
    """A token: cheaper than lark.Token, and all the parser needs."""

    __slots__ = ("type", "value", "start", "end")

    def __init__(self, type: str, value: str, start: int, end: int) -> None:
        self.type = type
        self.value = value
        self.start = start
        self.end = end

    def __repr__(self) -> str:
        return f"Tok({self.type}, {self.value!r}, {self.start}, {self.end})"


# the first characters of grammar.lark's NAME and INT
_NAME_START = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_")
_DIGITS = frozenset("0123456789")
_HINTS = {
    "=": "use ':=' to define a constant or '==' to compare",
    ":": "did you mean ':='?",
    "&": "did you mean '&&'?",
    "|": "did you mean '||'?",
}


@dataclass
class LexResult:
    tokens: list[Tok]
    comments: list[Comment]
    diagnostics: list[Diagnostic]
    after_error: set[int]  # indices of tokens that directly follow a lexical error


class Lexer:
    def __init__(self, terminals: list) -> None:  # lark TerminalDefs
        literal: list[tuple[str, str]] = []
        regex: dict[str, str] = {}
        self.keywords: dict[str, str] = {}
        word = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
        for term in terminals:
            pattern = term.pattern
            name = str(term.name)
            if type(pattern).__name__ == "PatternStr":
                if word.match(pattern.value):
                    self.keywords[str(pattern.value)] = name
                else:
                    literal.append((name, str(pattern.value)))
            else:
                regex[name] = pattern.to_regexp()
        literal.sort(key=lambda item: -len(item[1]))
        self.literals = {value: name for name, value in literal}
        self._types = {**self.keywords, **self.literals}  # the token text -> its type, but for NAME/INT
        # One match per token: (the white space before it, the token). The white space is atomic, so
        # that trailing white space never backtracks into a BAD token. The most frequent tokens are
        # tried first, longer punctuation before shorter. A '/*' without its '*/' takes the rest of
        # the text (the lexer stops there). Anything else is a one-character BAD token.
        space = f"(?>(?:{regex['WS']})?)"
        longer = [re.escape(value) for _, value in literal if len(value) > 1]
        single = "".join(re.escape(value) for _, value in literal if len(value) == 1)
        # comments before the one-character punctuation: '/' is an operator, '//' and '/*' are not
        token = "|".join([regex["NAME"], regex["INT"], *longer, regex["LINE_COMMENT"],
                          regex["BLOCK_COMMENT"], r"/\*(?:.|\n)*", f"[{single}]", r"[^ \t\f\r\n]"])
        self.scanner = re.compile(f"({space})({token})", re.ASCII)
        if self.scanner.groups != 2:
            raise ValueError("the regular expressions of grammar.lark's terminals must not capture: "
                             "write (?:...) for their groups")

    def lex(self, text: str, pos: int = 0, endpos: int | None = None) -> LexResult:
        """The tokens of ``text``, or of ``text[pos:endpos]`` (as for ``re``; offsets stay those of
        ``text``): a stretch that starts where a token can start."""
        tokens: list[Tok] = []
        comments: list[Comment] = []
        diagnostics: list[Diagnostic] = []
        after_error: set[int] = set()
        types = self._types
        append = tokens.append
        bad_start = -1
        bad_end = -1
        end = pos
        for space, value in self.scanner.findall(text, pos, len(text) if endpos is None else endpos):
            start = end + len(space)
            end = start + len(value)
            kind = types.get(value)
            if kind is None:
                first = value[0]
                if first in _NAME_START:
                    kind = "NAME"
                elif first in _DIGITS:
                    kind = "INT"
                elif value[:2] == "//":
                    comments.append(Comment(value, Span(start, end)))
                    continue
                elif value[:2] == "/*":
                    comments.append(Comment(value, Span(start, end)))
                    if len(value) < 4 or not value.endswith("*/"):  # runs to the end of the text
                        diagnostics.append(make(E_UNTERMINATED_COMMENT, Span(start, start + 2),
                                                "unterminated comment: this '/*' has no matching '*/'"))
                        break
                    continue
                elif value in _HINTS:  # kept as a BAD token: the parser tries what it may have meant
                    diagnostics.append(make(E_BAD_CHARACTER, Span(start, end),
                                            f"unexpected character {value!r}: {_HINTS[value]}"))
                    kind = "BAD"
                else:
                    if start == bad_end:
                        bad_end = end
                    else:
                        self._flush_bad(text, bad_start, bad_end, diagnostics)
                        bad_start, bad_end = start, end
                    after_error.add(len(tokens))
                    continue
            append(Tok(kind, value, start, end))
        self._flush_bad(text, bad_start, bad_end, diagnostics)
        diagnostics.sort(key=lambda d: d.span.start)
        return LexResult(tokens, comments, diagnostics, after_error)

    @staticmethod
    def _flush_bad(text: str, start: int, end: int, diagnostics: list[Diagnostic]) -> None:
        if start < 0:
            return
        chars = text[start:end]
        hint = _HINTS.get(chars, "")
        shown = chars if len(chars) <= 20 else chars[:20] + "…"
        message = f"unexpected character{'s' if len(chars) > 1 else ''} {shown!r}"
        if hint:
            message += f": {hint}"
        diagnostics.append(make(E_BAD_CHARACTER, Span(start, end), message))
