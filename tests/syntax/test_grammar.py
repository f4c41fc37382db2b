"""The grammar itself: LALR(1) with the dangling 'else' as its only conflict."""

from __future__ import annotations

import logging

from lark import Lark, logger

from rdcd_core.syntax.tables import GRAMMAR


def test_only_conflict_is_the_dangling_else(caplog) -> None:  # noqa: ANN001
    old_level = logger.level
    logger.setLevel(logging.DEBUG)
    try:
        with caplog.at_level(logging.DEBUG, logger="lark"):
            Lark(GRAMMAR.read_text(encoding="utf-8"), parser="lalr", lexer="basic", debug=True)
    finally:
        logger.setLevel(old_level)
    conflicts = [r.getMessage() for r in caplog.records if "conflict" in r.getMessage().lower()]
    assert conflicts, "the dangling else should show up as a (resolved) shift/reduce conflict"
    assert all("ELSE" in message for message in conflicts), conflicts
    assert not any("Reduce/Reduce" in message for message in conflicts)
