"""Bad input: the lexer never raises, on any text, the syntax fuzzers' mutated programs or huge
inputs; its tokens give back the text exactly (nothing dropped, nothing invented) and what is no
part of RDCD is an Error token, never an exception."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from pygments.token import Comment, Error, Keyword, Name

from rdcd_core.pygments_lexer import RdcdLexer
from rdcd_core.syntax.keywords import KEYWORDS
from tests.syntax.fuzz_inputs import PUNCT, edit, mutated_sources, spaced_tokens, tokens_of

SOURCES = mutated_sources()
VOCABULARY = [*KEYWORDS, *PUNCT, "self.", "neighbours.", "x", "Wheel", "sizeof", "EAST", "0", "300",
              "/*", "*/", "//", "\n", "\r\n", "\r", "=", "*", "/", "%", "@", "é", "\x00", "\ufeff", "\u2028"]


def lex(text: str) -> list[tuple[int, object, str]]:
    """The raw tokens of ``text`` (no newline added or stripped), checked to cover it exactly."""
    tokens = list(RdcdLexer().get_tokens_unprocessed(text))
    assert "".join(value for _, _, value in tokens) == text
    position = 0
    for start, _, value in tokens:
        assert start == position
        position += len(value)
    # and the processed stream, the one formatters read, does not raise either
    list(RdcdLexer().get_tokens(text))
    return tokens


@given(st.text(max_size=400))
def test_random_text(text: str) -> None:
    lex(text)


@given(st.text(alphabet="abxyzAB_019 \n\r\t{}();,.:=|&!<>+-/*%@é", max_size=400))
def test_random_text_from_the_language_alphabet(text: str) -> None:
    lex(text)


@given(st.lists(st.sampled_from(VOCABULARY), max_size=150), st.sampled_from([" ", "", "\n"]))
def test_random_token_sequences(tokens: list[str], separator: str) -> None:
    lex(separator.join(tokens))


_EDIT = st.tuples(st.sampled_from(["delete", "duplicate", "swap", "insert", "replace"]),
                  st.integers(0, 10**6), st.sampled_from(VOCABULARY))


@given(st.integers(0, len(SOURCES) - 1), st.lists(_EDIT, min_size=1, max_size=8), st.booleans())
def test_mutated_examples(which: int, edits: list[tuple[str, int, str]], keep_layout: bool) -> None:
    """The programs the syntax fuzzers mutate, edited token by token (with their layout kept, or
    joined by spaces as the parser's fuzzer does)."""
    tokens = spaced_tokens(SOURCES[which]) if keep_layout else tokens_of(SOURCES[which])
    for operation, position, word in edits:
        if not tokens:
            break
        edit(tokens, operation, position % len(tokens), word)
    lex(("" if keep_layout else " ").join(tokens))


@given(st.integers(0, len(SOURCES) - 1), st.integers(0, 10**6))
def test_every_prefix_of_an_example(which: int, cut: int) -> None:
    source = SOURCES[which]
    lex(source[: cut % (len(source) + 1)])


def test_huge_inputs() -> None:
    """Sizes far beyond any program: long runs that a careless pattern would backtrack over."""
    for text in ("/*" * 50_000, "self" + " " * 200_000, "self ." * 30_000, "a" * 200_000 + "(",
                 "(" * 100_000, "role " * 40_000, "x" + " \n" * 100_000 + "(", "@" * 50_000,
                 "deployment {" * 20_000, "// " + "x" * 300_000, "1" * 200_000):
        lex(text)


def test_what_is_not_rdcd_is_an_error_token_and_the_rest_goes_on() -> None:
    tokens = [(token, value) for _, token, value in lex("@role\x00é A") if value.strip()]
    assert tokens == [(Error, "@"), (Keyword.Declaration, "role"), (Error, "\x00"), (Error, "é"), (Name, "A")]


def test_an_unterminated_comment_runs_to_the_end() -> None:
    """As in the language's lexer (E002): the rest of the text is the comment."""
    assert [(t, v) for _, t, v in lex("role A { /* no end\nrole B { }")][-1] == (
        Comment.Multiline, "/* no end\nrole B { }")
