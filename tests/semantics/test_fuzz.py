"""The analysis never raises, whatever the parser recovers from mutated example programs."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.frontend import check_text
from rdcd_core.semantics import analyze
from rdcd_core.syntax.parser import parse
from tests.syntax.fuzz_inputs import mutated_sources, spaced_tokens

SOURCES = mutated_sources()
TOKENS = [spaced_tokens(text) for text in SOURCES]
VOCABULARY = sorted({t for tokens in TOKENS for t in tokens if not t.isspace()} | {
    "modifies", "extends", "abstract", "command", "behavior", "Module", "-128", "200", "{", "}",
    "(", ")", ";", ",", ".", "self", "Wheel", "Reverse", "Segment", "Head", "assumeRole",
    "handleEvent", "x", "==", "<", "!", "&&", "||", "+", "-"})

mutation = st.tuples(st.sampled_from(["replace", "delete", "insert", "duplicate"]),
                     st.integers(min_value=0, max_value=10_000),
                     st.integers(min_value=1, max_value=12),
                     st.sampled_from(VOCABULARY))


def _mutate(tokens: list[str], mutations: list[tuple[str, int, int, str]]) -> str:
    tokens = list(tokens)
    for kind, position, length, word in mutations:
        if not tokens:
            break
        i = position % len(tokens)
        if kind == "replace":
            tokens[i] = word
        elif kind == "delete":
            del tokens[i:i + length]
        elif kind == "insert":
            tokens.insert(i, " " + word + " ")
        else:
            tokens[i:i] = tokens[i:i + length]
    return "".join(tokens)


@given(st.integers(min_value=0, max_value=len(SOURCES) - 1), st.lists(mutation, min_size=1, max_size=6))
def test_analyze_never_raises(index: int, mutations: list[tuple[str, int, int, str]]) -> None:
    text = _mutate(TOKENS[index], mutations)
    model = analyze(parse(text).program)
    for diagnostic in model.diagnostics:
        assert 0 <= diagnostic.span.start <= diagnostic.span.end <= len(text)
        assert diagnostic.code[0] in "EW" and diagnostic.message
    result = check_text(text)
    assert all(d.code != "E100" for d in result.diagnostics)
