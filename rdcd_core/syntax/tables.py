"""The Lark LALR(1) tables for grammar.lark, built once per process (lazily) and shared."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from lark import Lark
from lark.parsers.lalr_analysis import Shift

from rdcd_core.syntax.builder import AstBuilder
from rdcd_core.syntax.lexer import Lexer

GRAMMAR = Path(__file__).with_name("grammar.lark")

# Nonterminals at whose start the parser can resynchronise after an error.
_SYNC_SYMBOLS = ("role", "member", "statement")


class Tables:
    """What the parse driver needs: the LALR table, the reduce callbacks and the lexer."""

    def __init__(self) -> None:
        lark = Lark(GRAMMAR.read_text(encoding="utf-8"), parser="lalr", lexer="basic",
                    transformer=AstBuilder(), maybe_placeholders=True, cache=True)
        inner = lark.parser.parser.parser  # ParsingFrontend -> LALR_Parser -> _Parser
        table = inner.parse_table
        self.start_state = table.start_states["start"]
        self.end_state = table.end_states["start"]
        # rule -> (number of symbols, nonterminal name, callback); the callback is None for the
        # unit rules of `?rule`s (most of the expression ladder), which pass their child through
        reduce_info = {rule: (len(rule.expansion), str(rule.origin.name),
                              None if _passes_through(rule) else inner.callbacks[rule])
                       for rule in lark.rules}
        # row[symbol] = (True, next state) for a shift or (False, reduce_info) for a reduce; plain
        # str keys and tuples because lark's Token.__eq__ and Rule.__hash__ are slow in the loop
        self.states: dict = {
            state: {str(symbol): (True, arg) if action is Shift else (False, reduce_info[arg])
                    for symbol, (action, arg) in row.items()}
            for state, row in table.states.items()}
        self.terminals = sorted(str(t.name) for t in lark.terminals)
        self.sync_states = frozenset(state for state, row in self.states.items()
                                     if any(symbol in row for symbol in _SYNC_SYMBOLS))
        self.lexer = Lexer(lark.terminals)


def _passes_through(rule) -> bool:  # noqa: ANN001 - a lark Rule
    return bool(rule.options.expand1 and len(rule.expansion) == 1 and rule.alias is None
                and not rule.expansion[0].name.startswith("_"))


@cache
def tables() -> Tables:
    return Tables()
