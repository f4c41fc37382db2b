"""The Pygments lexer over every RDCD program a reader meets: each example, each step of the
tutorial and each ```rdcd block of the documentation and the README (snippets included) lexes
with no Error token; and every code block of the docs says its language, so that none of RDCD is
left grey."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from pygments.lexers import get_lexer_by_name
from pygments.token import Error, Keyword

from rdcd_core.pygments_lexer import RdcdLexer
from tests.conftest import EXAMPLES, ROOT

DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})(?P<info>[^\n`]*)$")
SNIPPET = re.compile(r'^\s*--8<--\s+"([^"]+)"\s*$')
# what only RDCD looks like: a line that opens a role or the deployment
LOOKS_LIKE_RDCD = re.compile(r"^\s*(?:(?:abstract\s+)?role\s+\w+\s*(?:(?:extends|modifies)\s+\w+\s*)?\{"
                             r"|deployment\s*\{)", re.M)


def code_blocks(path: Path) -> list[tuple[int, str, str]]:
    """(line, language, text) of each fenced block of ``path``, snippets (pymdownx.snippets)
    replaced by the file they name."""
    blocks: list[tuple[int, str, str]] = []
    lines = path.read_text(encoding="utf-8").split("\n")
    open_at: tuple[int, str, str] | None = None  # (line, fence, language)
    body: list[str] = []
    for number, line in enumerate(lines, 1):
        match = FENCE.match(line)
        if open_at is None:
            if match:
                open_at, body = (number, match["fence"], match["info"].strip().split(" ")[0]), []
        elif match and match["fence"].startswith(open_at[1]) and not match["info"].strip():
            blocks.append((open_at[0], open_at[2], "\n".join(body) + "\n"))
            open_at = None
        else:
            snippet = SNIPPET.match(line)
            body.append((ROOT / snippet[1]).read_text(encoding="utf-8").rstrip("\n") if snippet else line)
    assert open_at is None, f"{path}:{open_at[0]}: a fence that is never closed"
    return blocks


BLOCKS = [(f"{path.relative_to(ROOT)}:{line}", language, text)
          for path in DOCUMENTS for line, language, text in code_blocks(path)]
RDCD_BLOCKS = [(where, text) for where, language, text in BLOCKS if language == "rdcd"]
PROGRAMS = [(str(path.relative_to(ROOT)), path.read_text(encoding="utf-8"))
            for path in sorted([*EXAMPLES.glob("*.rdcd"), *(ROOT / "docs").rglob("*.rdcd")])]


def errors(text: str) -> list[tuple[int, str]]:
    return [(at, value) for at, token, value in RdcdLexer().get_tokens_unprocessed(text) if token in Error]


@pytest.mark.parametrize(("where", "text"), PROGRAMS, ids=[w for w, _ in PROGRAMS])
def test_no_error_token_in_an_example(where: str, text: str) -> None:
    assert errors(text) == [], where
    assert any(token in Keyword for _, token, _ in RdcdLexer().get_tokens_unprocessed(text)), where


@pytest.mark.parametrize(("where", "text"), RDCD_BLOCKS, ids=[w for w, _ in RDCD_BLOCKS])
def test_no_error_token_in_a_block_of_the_docs(where: str, text: str) -> None:
    assert errors(text) == [], where


def test_the_docs_show_rdcd_and_all_of_it() -> None:
    """Enough RDCD blocks that the scan works (the examples, the tutorial, the reference), and the
    snippets of examples are among them."""
    assert len(RDCD_BLOCKS) >= 50
    assert any("deployment" in text and where.startswith("docs/tutorial.md") for where, text in RDCD_BLOCKS)
    assert len(PROGRAMS) >= 9


def test_every_code_block_says_its_language() -> None:
    """A bare fence is drawn grey: each block names its language (``text`` for one that has none)."""
    bare = [where for where, language, _ in BLOCKS if not language]
    assert bare == [], f"fences without a language: {bare}"


def test_every_language_of_the_docs_has_a_pygments_lexer() -> None:
    """pymdownx.highlight colours a block through the lexer its language names (``text``: none)."""
    for where, language, text in BLOCKS:
        lexer = get_lexer_by_name(language)  # raises ClassNotFound for a language Pygments lacks
        if language not in ("rdcd", "text"):
            shown = [(token, value) for token, value in lexer.get_tokens(text) if token in Error]
            assert shown == [], (where, language, shown)


def test_every_block_of_rdcd_is_marked_rdcd() -> None:
    unmarked = [(where, language) for where, language, text in BLOCKS
                if language != "rdcd" and LOOKS_LIKE_RDCD.search(text)]
    assert unmarked == [], f"RDCD in blocks not marked ```rdcd: {unmarked}"


def test_a_bad_character_is_an_error_token() -> None:
    """The scan can fail: what is no part of RDCD is an Error token (and only that)."""
    assert errors("role A { @ } // é is fine in a comment\n") == [(9, "@")]
    assert errors("state é := 1;") == [(6, "é")]
