"""The Pygments lexer, the TextMate grammar of the VS Code extension and the checker's tables agree:
the same keywords (each coloured as the grammar's scope says), Module API primitives, predefined
values and operators (docs/architecture.md rule 1). A word added to a table and the grammar is
coloured by the lexer with no change to it; one missing from either side fails here."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from pygments.token import Keyword, Name, Operator, Punctuation, _TokenType

from rdcd_core.module_api import PRIMITIVES, CallForm
from rdcd_core.operators import BINARY, UNARY
from rdcd_core.pygments_lexer import (
    DECLARATION_WORDS,
    DECLARES,
    GRAMMAR,
    PSEUDO_NAMES,
    RdcdLexer,
    grammar_terminals,
)
from rdcd_core.syntax.keywords import KEYWORDS
from rdcd_core.syntax.tables import tables
from rdcd_core.types import PREDEFINED_VALUES

TEXTMATE = Path(__file__).resolve().parents[2] / "vscode-extension" / "syntaxes" / "rdcd.tmLanguage.json"
WORD_GROUP = re.compile(r"\(\?:((?:[A-Za-z_][A-Za-z0-9_]*\|)*[A-Za-z_][A-Za-z0-9_]*)\)")
# The Pygments token (or family) of each TextMate scope of the grammar's keywords: a keyword is drawn
# in the keyword colour whatever its kind (the site's theme draws k, kd, kr... alike), and a name the
# language gives (self, neighbours) is a pseudo built-in.
SCOPE_TOKENS: list[tuple[str, _TokenType]] = [
    ("variable.language", Name.Builtin.Pseudo),
    ("storage.", Keyword),
    ("keyword.", Keyword),
]
SELF = [p.name for p in PRIMITIVES if p.form is CallForm.SELF]
FUNCTIONS = [p.name for p in PRIMITIVES if p.form is CallForm.FUNCTION]
# words that are in no table: the lexer must not colour them as if they were
NOT_IN_ANY_TABLE = ["Wheel", "spread", "hops", "foo", "East", "SELF", "Role", "abstracts", "x1"]


@pytest.fixture(scope="module")
def grammar() -> dict[str, Any]:
    return json.loads(TEXTMATE.read_text(encoding="utf-8"))


def lex(text: str) -> list[tuple[_TokenType, str]]:
    return [(t, v) for t, v in RdcdLexer().get_tokens(text) if v.strip()]


def token_of(word: str) -> _TokenType:
    tokens = lex(word)
    assert len(tokens) == 1, (word, tokens)
    return tokens[0][0]


def _words(patterns: list[dict[str, Any]]) -> list[str]:
    return [w for p in patterns for group in WORD_GROUP.findall(p.get("match", "")) for w in group.split("|")]


def _scope_token(scope: str) -> _TokenType:
    return next(token for prefix, token in SCOPE_TOKENS if scope.startswith(prefix))


def test_keywords_are_coloured_as_the_grammar_scopes_them(grammar: dict[str, Any]) -> None:
    scoped = {w: p["name"] for p in grammar["repository"]["keywords"]["patterns"] for w in _words([p])}
    assert sorted(scoped) == sorted(KEYWORDS) == sorted(tables().lexer.keywords)
    for word, scope in scoped.items():
        assert token_of(word) in _scope_token(scope), f"{word!r}: the grammar scopes it {scope}"


def test_the_lexers_own_keyword_lists_name_only_keywords() -> None:
    stale = ({*DECLARES, *DECLARATION_WORDS, *PSEUDO_NAMES}) - set(KEYWORDS)
    assert not stale, f"{sorted(stale)} in rdcd_core/pygments_lexer.py: no keyword of RDCD"


def test_only_keywords_are_keywords() -> None:
    for word in [*SELF, *FUNCTIONS, *PREDEFINED_VALUES, *NOT_IN_ANY_TABLE]:
        token = token_of(word)
        assert token not in Keyword and token is not Name.Builtin.Pseudo, (word, token)


def test_self_primitives_equal_the_grammar_and_the_module_api(grammar: dict[str, Any]) -> None:
    listed = _words(grammar["repository"]["self-call"]["patterns"][:1])
    assert sorted(listed) == sorted(SELF)
    for word in listed:
        for text in (f"self.{word}", f"self . {word}()", f"self.{word}(EAST)"):
            assert lex(text)[:3] == [(Name.Builtin.Pseudo, "self"), (Punctuation, "."), (Name.Builtin, word)]
    for word in [*FUNCTIONS, *NOT_IN_ANY_TABLE]:
        assert lex(f"self.{word}()")[2] == (Name.Function, word), "a method of the program's own"


def test_function_primitives_equal_the_grammar_and_the_module_api(grammar: dict[str, Any]) -> None:
    listed = _words([grammar["repository"]["function-primitives"]])
    assert sorted(listed) == sorted(FUNCTIONS)
    for word in listed:
        assert lex(f"{word}(neighbours.s)")[0] == (Name.Builtin, word)
        assert lex(f"{word} (1, 2)")[0] == (Name.Builtin, word)
    for word in [*SELF, *NOT_IN_ANY_TABLE]:
        assert lex(f"{word}(1)")[0] == (Name.Function, word)


def test_predefined_values_equal_the_grammar_and_the_types_table(grammar: dict[str, Any]) -> None:
    listed = _words(grammar["repository"]["predefined-values"]["patterns"])
    assert sorted(listed) == sorted(PREDEFINED_VALUES)
    for word in listed:
        assert token_of(word) is Name.Constant
    for word in NOT_IN_ANY_TABLE:
        assert token_of(word) is Name


def _textmate_operators(grammar: dict[str, Any]) -> set[str]:
    found: set[str] = set()
    for pattern in grammar["repository"]["operators"]["patterns"]:
        for alternative in re.split(r"(?<!\\)\|", pattern["match"]):
            found.add(re.sub(r"\\(.)", r"\1", alternative))
    return found


def test_operators_equal_the_grammar_and_the_operator_table(grammar: dict[str, Any]) -> None:
    table = {*BINARY, *UNARY, ":="}
    assert _textmate_operators(grammar) == table, "the TextMate grammar's operators are not the table's"
    for symbol in table:
        assert lex(f"a {symbol} b") == [(Name, "a"), (Operator, symbol), (Name, "b")]


def test_every_terminal_of_grammar_lark_is_one_token() -> None:
    keywords, literals = grammar_terminals(GRAMMAR.read_text(encoding="utf-8"))
    assert set(literals) == set(tables().lexer.literals), "grammar_terminals() misreads grammar.lark"
    assert sorted(keywords) == sorted(tables().lexer.keywords) == sorted(KEYWORDS)
    operators = {*BINARY, *UNARY, ":="}
    for symbol in literals:
        assert lex(symbol) == [(Operator if symbol in operators else Punctuation, symbol)]


@pytest.mark.parametrize("symbol", ["*", "/", "%", "=", "&", "|", ":", "^", "~"])
def test_an_operator_no_table_has_yet_is_still_an_operator(symbol: str) -> None:
    """Operators are generic: one a branch adds to the language is coloured before any table here
    knows it, and `x = 1` (a mistake the diagnostics page shows) reads as code."""
    assert lex(f"a {symbol} b") == [(Name, "a"), (Operator, symbol), (Name, "b")]


def test_declarations_colour_the_name_they_declare() -> None:
    program = ("abstract role Wheel extends Base { constant SPEED := 3; travelling state hops := 0;"
               " startup go() { Base.stop(); self.assumeRole(M, { }); } } role M modifies Wheel { }"
               " deployment { Wheel, M }")
    tokens = lex(program)
    assert (Name.Class, "Wheel") in tokens and (Name.Class, "Base") in tokens
    assert (Name.Constant, "SPEED") in tokens and (Name.Variable, "hops") in tokens
    assert (Name.Function, "go") in tokens and (Name.Function, "stop") in tokens
    assert tokens[tokens.index((Name.Builtin, "assumeRole")) + 2] == (Name.Class, "M")
    assert tokens[-5:] == [(Punctuation, "{"), (Name.Class, "Wheel"), (Punctuation, ","), (Name.Class, "M"),
                           (Punctuation, "}")]
    assert [v for t, v in tokens if t in Keyword] == ["abstract", "role", "extends", "constant", "travelling",
                                                      "state", "startup", "role", "modifies", "deployment"]


def test_the_lexer_is_registered_for_rdcd_files() -> None:
    assert RdcdLexer.aliases == ["rdcd"] and RdcdLexer.filenames == ["*.rdcd"]
