"""A Pygments lexer for RDCD, registered under the name ``rdcd`` (pyproject.toml's
``pygments.lexers`` entry point): MkDocs (``pymdownx.highlight``), Sphinx, Jupyter and ``pygmentize``
colour RDCD through it.

Its word lists are the checker's, like the TextMate grammar's (docs/architecture.md rule 1): the
keywords, punctuation and operators are grammar.lark's literal terminals (which the language's own
lexer reads; ``rdcd_core.syntax.keywords`` agrees with them), an operator being a symbol of
``rdcd_core.operators`` or ``:=``; the Module API is ``rdcd_core.module_api``'s table and the
predefined values ``rdcd_core.types``'. A keyword, primitive or operator added there is coloured
with no change here; tests/highlight/test_lexer_tables.py fails when the lexer, the TextMate grammar
and the tables disagree. What is written here is only what no table says: which token a kind of
keyword is. (grammar.lark is read as text, not through ``rdcd_core.syntax``, whose parser would
add a fifth of a second to every documentation build.)

The lexer never raises (Pygments' RegexLexer makes a one-character ``Error`` token of what no rule
matches). Operator characters are operators even where the language has no such operator (``=``,
``*``), so that a wrong program in the documentation still reads as code; a character that is no
part of RDCD (``@``, ``é``) is an ``Error`` token.
"""

from __future__ import annotations

import re
from pathlib import Path

from pygments.lexer import RegexLexer, bygroups, default, words
from pygments.token import (
    Comment,
    Keyword,
    Name,
    Number,
    Operator,
    Punctuation,
    Whitespace,
    _TokenType,
)

from rdcd_core.module_api import PRIMITIVES, CallForm
from rdcd_core.operators import BINARY, UNARY
from rdcd_core.types import PREDEFINED_VALUES, Type

__all__ = ["RdcdLexer"]

GRAMMAR = Path(__file__).resolve().parent / "syntax" / "grammar.lark"

# grammar.lark's NAME and WS; a keyword or a name ends where a NAME could not go on
NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_END = r"(?![A-Za-z0-9_])"
_WS = r"[ \t\f\r\n\ufeff]+"
_SPACE = r"[ \t\f\r\n\ufeff]*"

# The token of each kind of keyword, and of the name it declares (None: it declares none). A keyword
# of the table that is not listed here is a plain Keyword; a word listed here that is no keyword is
# an error (the test says so).
DECLARES: dict[str, _TokenType | None] = {
    "role": Name.Class, "extends": Name.Class, "modifies": Name.Class,
    "constant": Name.Constant, "state": Name.Variable,
    "startup": Name.Function, "behavior": Name.Function, "command": Name.Function,
}
DECLARATION_WORDS = ("abstract", "travelling", "deployment", *DECLARES)  # Keyword.Declaration
PSEUDO_NAMES = ("self", "neighbours", "children")  # Name.Builtin.Pseudo: names the language gives
# Operator characters outside comments: those of the operator table, and those of likely operators
# (a wrong `=`, or an operator another version has), so that a new operator is coloured at once.
_LIKELY_OPERATOR_CHARACTERS = "=:*/%&|^~"


def keyword_token(word: str) -> _TokenType:
    if word in PSEUDO_NAMES:
        return Name.Builtin.Pseudo
    if word in DECLARATION_WORDS:
        return Keyword.Declaration
    return Keyword


def grammar_terminals(text: str) -> tuple[list[str], list[str]]:
    """The literal terminals of grammar.lark (``NAME: "text"``): (its keywords, its punctuation and
    operators)."""
    found = [value.encode().decode("unicode_escape")
             for value in re.findall(r'^[A-Z][A-Z0-9_]*\s*:\s*"((?:[^"\\]|\\.)*)"', text, re.M)]
    return ([value for value in found if re.fullmatch(NAME, value)],
            [value for value in found if not re.fullmatch(NAME, value)])


def operator_symbols() -> list[str]:
    """Every operator of the language: the operator table's symbols and ``:=``."""
    return sorted({*BINARY, *UNARY, ":="}, key=lambda s: (-len(s), s))


def _alternatives(names: list[str]) -> str:
    """A regular expression for any of ``names`` (the longest first, so that none stops short)."""
    return "|".join(re.escape(name) for name in sorted(names, key=lambda n: (-len(n), n)))


def _rules() -> dict[str, list]:
    self_primitives = [p.name for p in PRIMITIVES if p.form is CallForm.SELF]
    # self.assumeRole(M, ...): a primitive whose first argument is a role names one
    role_first = [p.name for p in PRIMITIVES if p.form is CallForm.SELF and p.params[:1]
                  and p.params[0].type is Type.ROLE]
    functions = [p.name for p in PRIMITIVES if p.form is CallForm.FUNCTION]
    operators = operator_symbols()
    keywords, literals = grammar_terminals(GRAMMAR.read_text(encoding="utf-8"))
    punctuation = sorted((s for s in literals if s not in operators), key=lambda s: (-len(s), s))
    operator_characters = {*"".join(operators), *_LIKELY_OPERATOR_CHARACTERS} - {*"".join(punctuation)}
    comments = [
        (r"//[^\r\n]*", Comment.Single),
        (r"/\*[\s\S]*?\*/", Comment.Multiline),
        (r"/\*[\s\S]*", Comment.Multiline),  # unterminated: the language's lexer takes the rest too
    ]
    by_kind: dict[_TokenType, list[str]] = {}
    for word in keywords:
        by_kind.setdefault(keyword_token(word), []).append(word)
    declarations = [
        (f"({word})({_WS})({NAME})", bygroups(keyword_token(word), Whitespace, token))
        for word, token in DECLARES.items() if word in keywords and token is not None
    ]
    root = [
        (_WS, Whitespace),
        *comments,
        *declarations,
        (rf"(deployment)({_SPACE})(\{{)", bygroups(keyword_token("deployment"), Whitespace, Punctuation),
         "deployment"),
        *([(rf"(self)({_SPACE})(\.)({_SPACE})({_alternatives(role_first)})({_SPACE})(\()({_SPACE})({NAME})",
             bygroups(Name.Builtin.Pseudo, Whitespace, Punctuation, Whitespace, Name.Builtin, Whitespace,
                      Punctuation, Whitespace, Name.Class))] if role_first else []),
        (rf"(self)({_SPACE})(\.)({_SPACE})({_alternatives(self_primitives)}){_END}",
         bygroups(Name.Builtin.Pseudo, Whitespace, Punctuation, Whitespace, Name.Builtin)),
        (rf"(self)({_SPACE})(\.)({_SPACE})({NAME})",
         bygroups(Name.Builtin.Pseudo, Whitespace, Punctuation, Whitespace, Name.Function)),
        (rf"(neighbours|children)({_SPACE})(\.)({_SPACE})({NAME})",
         bygroups(Name.Builtin.Pseudo, Whitespace, Punctuation, Whitespace, Name.Variable)),
        (words(functions, suffix=rf"{_END}(?={_SPACE}\()"), Name.Builtin),
        *((words(group, suffix=_END), token) for token, group in by_kind.items()),
        (words(list(PREDEFINED_VALUES), suffix=_END), Name.Constant),
        # Role.command(...): a global command call
        (rf"({NAME})({_SPACE})(\.)({_SPACE})({NAME})(?={_SPACE}\()",
         bygroups(Name.Class, Whitespace, Punctuation, Whitespace, Name.Function)),
        (rf"{NAME}(?={_SPACE}\()", Name.Function),
        (NAME, Name),
        (r"[0-9]+", Number.Integer),
        (words(operators), Operator),
        (words(punctuation), Punctuation),
        ("[" + re.escape("".join(sorted(operator_characters))) + "]", Operator),
    ]
    deployment = [
        (_WS, Whitespace),
        *comments,
        (NAME, Name.Class),
        (",", Punctuation),
        (r"\}", Punctuation, "#pop"),
        default("#pop"),
    ]
    return {"root": root, "deployment": deployment}


class RdcdLexer(RegexLexer):
    """RDCD, the role-based language for ATRON modular robots (docs/language.md)."""

    name = "RDCD"
    aliases = ["rdcd"]
    filenames = ["*.rdcd"]
    mimetypes = ["text/x-rdcd"]
    tokens = _rules()
