"""Fuzz inputs shared by the fuzz tests (syntax, semantics, the VM's whole chain) and
benchmarks/parse_fuzz.py: the example programs cut into tokens, the language's punctuation, and
token-level edits."""

from __future__ import annotations

import re
from pathlib import Path

from hypothesis import strategies as st

EXAMPLES = Path(__file__).resolve().parent.parent.parent / "examples"
TOKEN_RE = re.compile(r"//[^\n]*|/\*.*?\*/|[A-Za-z_]\w*|\d+|:=|\|\||&&|==|!=|<=|>=|\S", re.S)
PUNCT = ["{", "}", "(", ")", ",", ";", ".", ":=", "||", "&&", "==", "!=", "<", ">", "<=", ">=",
         "+", "-", "!"]


# the programs the checker's and the VM's fuzzers mutate: the two examples and Figure 5 as printed
MUTATED_EXAMPLES = ("obstacle_avoidance.rdcd", "snake_wave.rdcd", "figure5_verbatim.rdcd", "gradient.rdcd",
                    "hops.rdcd", "count.rdcd", "lowest.rdcd")


def example_sources() -> list[str]:
    return [path.read_text(encoding="utf-8") for path in sorted(EXAMPLES.glob("*.rdcd"))]


def mutated_sources() -> list[str]:
    return [(EXAMPLES / name).read_text(encoding="utf-8") for name in MUTATED_EXAMPLES]


def spaced_tokens(text: str) -> list[str]:
    """``text`` cut into words, single other characters and runs of whitespace: joined, they give
    ``text`` back, so an edit keeps the rest of the program as it was written."""
    return re.findall(r"\w+|\S|\s+", text)


def tokens_of(text: str) -> list[str]:
    """``text`` cut into tokens (comments kept whole, whitespace dropped)."""
    return TOKEN_RE.findall(text)


def edit(tokens: list[str], operation: str, index: int, word: str) -> None:
    """Applies one edit to ``tokens[index]`` in place: delete, duplicate, swap (with the next
    token; nothing at the end), insert ``word`` before it, or replace it with ``word``."""
    if operation == "delete":
        del tokens[index]
    elif operation == "duplicate":
        tokens.insert(index, tokens[index])
    elif operation == "swap":
        if index + 1 < len(tokens):
            tokens[index], tokens[index + 1] = tokens[index + 1], tokens[index]
    elif operation == "insert":
        tokens.insert(index, word)
    else:
        tokens[index] = word


def nested_statements(simple: list[str], conditions: list[str], depth: int,
                      blocks: tuple[str, ...] = ()) -> st.SearchStrategy[str]:
    """Random statement lists up to ``depth`` levels: ``simple`` statements, ``if``/``else`` on
    ``conditions``, and each of ``blocks`` (a format with one ``{body}``) around an inner list."""
    plain = st.sampled_from(simple)
    if depth == 0:
        return plain
    inner = st.lists(nested_statements(simple, conditions, depth - 1, blocks), max_size=3).map(" ".join)
    condition = st.sampled_from(conditions)
    return st.one_of(
        plain,
        st.builds(lambda c, a, b: f"if ({c}) {{ {a} }} else {{ {b} }}", condition, inner, inner),
        st.builds(lambda c, a: f"if ({c}) {{ {a} }}", condition, inner),
        *(inner.map(lambda a, block=block: block.format(body=a)) for block in blocks),
    )
