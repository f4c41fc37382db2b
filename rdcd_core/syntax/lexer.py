"""The RDCD lexer, derived from the terminals of grammar.lark.

One master regular expression, built from the grammar's terminal definitions, splits the text;
keywords are NAME matches looked up in a table. Comments are kept (for ``Program.comments``).
Bad characters and an unterminated ``/*`` become diagnostics: the lexer never raises.
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


_IGNORED = ("WS", "LINE_COMMENT", "BLOCK_COMMENT")
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
        parts = [f"(?P<{name}>{regex[name]})" for name in _IGNORED]
        parts.append(r"(?P<OPEN_COMMENT>/\*)")
        parts.append(f"(?P<NAME>{regex['NAME']})")
        parts.append(f"(?P<INT>{regex['INT']})")
        parts.append("(?P<PUNCT>" + "|".join(re.escape(value) for _, value in literal) + ")")
        parts.append("(?P<HINTED>[" + re.escape("".join(_HINTS)) + "])")
        parts.append(r"(?P<BAD>[^ \t\f\r\n])")
        self.master = re.compile("|".join(parts), re.ASCII)

    def lex(self, text: str) -> LexResult:
        tokens: list[Tok] = []
        comments: list[Comment] = []
        diagnostics: list[Diagnostic] = []
        after_error: set[int] = set()
        keywords = self.keywords
        literals = self.literals
        append = tokens.append
        bad_start = -1
        bad_end = -1
        for match in self.master.finditer(text):
            kind = match.lastgroup
            if kind == "NAME":
                value = match.group()
                append(Tok(keywords.get(value, "NAME"), value, match.start(), match.end()))
                continue
            if kind == "PUNCT":
                value = match.group()
                append(Tok(literals[value], value, match.start(), match.end()))
                continue
            if kind == "INT":
                append(Tok("INT", match.group(), match.start(), match.end()))
                continue
            if kind == "WS":
                continue
            start = match.start()
            if kind == "HINTED":  # kept as a BAD token: the parser tries what it may have meant
                value = match.group()
                diagnostics.append(make(E_BAD_CHARACTER, Span(start, match.end()),
                                        f"unexpected character {value!r}: {_HINTS[value]}"))
                append(Tok("BAD", value, start, match.end()))
                continue
            if kind == "BAD":
                if start == bad_end:
                    bad_end = match.end()
                else:
                    self._flush_bad(text, bad_start, bad_end, diagnostics)
                    bad_start, bad_end = start, match.end()
                after_error.add(len(tokens))
                continue
            if kind == "OPEN_COMMENT":  # a /* without its */: the comment runs to the end
                comments.append(Comment(text[start:], Span(start, len(text))))
                diagnostics.append(make(E_UNTERMINATED_COMMENT, Span(start, start + 2),
                                        "unterminated comment: this '/*' has no matching '*/'"))
                break
            comments.append(Comment(match.group(), Span(start, match.end())))
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
