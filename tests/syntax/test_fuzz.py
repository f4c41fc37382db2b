"""Property tests: no input makes the parser raise, and every range it reports lies in the text."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.syntax import ast, parse
from rdcd_core.syntax.keywords import KEYWORDS
from tests.syntax.fuzz_inputs import PUNCT, edit, example_sources, tokens_of
from tests.syntax.helpers import check_spans

SOURCES = example_sources()
EXAMPLE_TOKENS = [tokens_of(source) for source in SOURCES]
VOCABULARY = [*KEYWORDS, *PUNCT, "x", "Wheel", "sizeof", "0", "300", "/*", "*/", "//", "\n",
              "=", "@", "é", "\x00"]


def check(text: str) -> None:
    result = parse(text)
    assert isinstance(result.program, ast.Program)
    check_spans(text, result.program)
    for diagnostic in result.diagnostics:
        assert 0 <= diagnostic.span.start <= diagnostic.span.end <= len(text), diagnostic
        for related in diagnostic.related:
            assert 0 <= related.span.start <= related.span.end <= len(text)
        assert diagnostic.message


@given(st.text(max_size=300))
def test_random_text(text: str) -> None:
    check(text)


@given(st.text(alphabet="abxyzAB_019 \n{}();,.:=|&!<>+-/*@", max_size=300))
def test_random_text_from_the_language_alphabet(text: str) -> None:
    check(text)


@given(st.lists(st.sampled_from(VOCABULARY), max_size=150), st.sampled_from([" ", "", "\n"]))
def test_random_token_sequences(tokens: list[str], separator: str) -> None:
    check(separator.join(tokens))


_EDIT = st.tuples(st.sampled_from(["delete", "duplicate", "swap", "insert"]), st.integers(0, 10**6),
                  st.sampled_from(VOCABULARY))


@given(st.integers(0, len(SOURCES) - 1), st.lists(_EDIT, min_size=1, max_size=5))
def test_mutated_examples(which: int, edits: list[tuple[str, int, str]]) -> None:
    tokens = list(EXAMPLE_TOKENS[which])
    for operation, position, word in edits:
        if not tokens:
            break
        edit(tokens, operation, position % len(tokens), word)
    check(" ".join(tokens))


@given(st.integers(0, len(SOURCES) - 1), st.integers(0, 10**6))
def test_every_prefix_of_an_example(which: int, cut: int) -> None:
    """What an editor sees while the user types."""
    source = SOURCES[which]
    text = source[:cut % (len(source) + 1)]
    check(text)


@given(st.integers(0, len(EXAMPLE_TOKENS) - 1), st.integers(0, 10**6))
def test_one_deleted_token_gives_few_errors(which: int, position: int) -> None:
    tokens = [t for t in EXAMPLE_TOKENS[which] if not t.startswith("/")]
    del tokens[position % len(tokens)]
    result = parse(" ".join(tokens))
    baseline = len(parse(" ".join(t for t in EXAMPLE_TOKENS[which] if not t.startswith("/"))).diagnostics)
    assert len(result.diagnostics) <= baseline + 3
