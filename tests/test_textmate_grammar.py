"""The TextMate grammar of the VS Code extension lists the same keywords, Module API primitives and
predefined values as the tables in rdcd_core (docs/architecture.md rule 1: the grammar is the only
other list)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from rdcd_core.module_api import PRIMITIVES, CallForm
from rdcd_core.syntax.keywords import KEYWORDS
from rdcd_core.types import PREDEFINED_VALUES

GRAMMAR_PATH = Path(__file__).resolve().parents[1] / "vscode-extension" / "syntaxes" / "rdcd.tmLanguage.json"
# A word list in the grammar is written as a non-capturing group of plain alternatives.
WORD_GROUP = re.compile(r"\(\?:((?:[A-Za-z_][A-Za-z0-9_]*\|)*[A-Za-z_][A-Za-z0-9_]*)\)")


@pytest.fixture(scope="module")
def grammar() -> dict[str, Any]:
    return json.loads(GRAMMAR_PATH.read_text(encoding="utf-8"))


def _patterns(rule: dict[str, Any]) -> list[dict[str, Any]]:
    return rule.get("patterns", [rule])


def _words(rule: dict[str, Any]) -> list[str]:
    words: list[str] = []
    for pattern in _patterns(rule):
        for group in WORD_GROUP.findall(pattern.get("match", "")):
            words.extend(group.split("|"))
    return words


def _all_matches(node: Any) -> list[str]:
    if isinstance(node, dict):
        found = [node[key] for key in ("match", "begin", "end") if isinstance(node.get(key), str)]
        for value in node.values():
            found.extend(_all_matches(value))
        return found
    if isinstance(node, list):
        return [match for item in node for match in _all_matches(item)]
    return []


def test_keywords_equal_the_language_keywords(grammar: dict[str, Any]) -> None:
    words = _words(grammar["repository"]["keywords"])
    assert len(words) == len(set(words)), "a keyword is listed twice"
    assert sorted(words) == sorted(KEYWORDS)


def test_self_primitives_equal_the_module_api(grammar: dict[str, Any]) -> None:
    primitive_rule = grammar["repository"]["self-call"]["patterns"][0]
    words = _words(primitive_rule)
    expected = [p.name for p in PRIMITIVES if p.form is CallForm.SELF]
    assert len(words) == len(set(words))
    assert sorted(words) == sorted(expected)


def test_function_primitives_equal_the_module_api(grammar: dict[str, Any]) -> None:
    words = _words(grammar["repository"]["function-primitives"])
    expected = [p.name for p in PRIMITIVES if p.form is CallForm.FUNCTION]
    assert sorted(words) == sorted(expected)


def test_all_primitives_are_covered(grammar: dict[str, Any]) -> None:
    repository = grammar["repository"]
    listed = set(_words(repository["self-call"]["patterns"][0]))
    listed |= set(_words(repository["function-primitives"]))
    assert listed == {p.name for p in PRIMITIVES}


def test_predefined_values_equal_the_types_table(grammar: dict[str, Any]) -> None:
    words = _words(grammar["repository"]["predefined-values"])
    assert len(words) == len(set(words))
    assert sorted(words) == sorted(PREDEFINED_VALUES)


def test_no_stale_names_anywhere_in_the_grammar(grammar: dict[str, Any]) -> None:
    known = set(KEYWORDS) | {p.name for p in PRIMITIVES} | set(PREDEFINED_VALUES)
    for match in _all_matches(grammar):
        for group in WORD_GROUP.findall(match):
            unknown = set(group.split("|")) - known
            assert not unknown, f"{sorted(unknown)} in {match!r}: not a keyword, primitive or value"


def test_grammar_is_wired_into_the_top_level(grammar: dict[str, Any]) -> None:
    assert grammar["scopeName"] == "source.rdcd"
    statements = {p["include"] for p in grammar["repository"]["statements"]["patterns"]}
    assert {"#keywords", "#self-call", "#function-primitives", "#predefined-values"} <= statements
    top = {p["include"] for p in grammar["patterns"]}
    assert "#statements" in top and "#comments" in top


def test_every_operator_of_the_table_is_coloured(grammar: dict[str, Any]) -> None:
    """Each binary and unary operator of rdcd_core.operators (issue 25 added * / %) is matched by one
    of the grammar's operator patterns, and '//' still begins a comment."""
    from rdcd_core.operators import BINARY, UNARY

    patterns = [re.compile(p["match"]) for p in grammar["repository"]["operators"]["patterns"]]
    for symbol in {*BINARY, *UNARY}:
        assert any(p.fullmatch(symbol) for p in patterns), symbol
    comments = json.dumps(grammar["repository"].get("comments", {}))
    assert "//" in comments or "\\\\/\\\\/" in comments
