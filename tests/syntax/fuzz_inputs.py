"""Fuzz inputs shared by tests/syntax/test_fuzz.py and benchmarks/parse_fuzz.py: the example
programs cut into tokens, the language's punctuation, and token-level edits."""

from __future__ import annotations

import re
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parent.parent.parent / "examples"
TOKEN_RE = re.compile(r"//[^\n]*|/\*.*?\*/|[A-Za-z_]\w*|\d+|:=|\|\||&&|==|!=|<=|>=|\S", re.S)
PUNCT = ["{", "}", "(", ")", ",", ";", ".", ":=", "||", "&&", "==", "!=", "<", ">", "<=", ">=",
         "+", "-", "!"]


def example_sources() -> list[str]:
    return [path.read_text(encoding="utf-8") for path in sorted(EXAMPLES.glob("*.rdcd"))]


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
