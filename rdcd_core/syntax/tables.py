"""The Lark LALR(1) tables for grammar.lark, built once per process (lazily) and shared."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from lark import Lark, Tree
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
                              None if _passes_through(rule) else
                              _extend_items if _continues_repetition(rule) else inner.callbacks[rule])
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
        self.role_states = frozenset(state for state, row in self.states.items() if "role" in row)
        self.lexer = Lexer(lark.terminals)
        # (state below, state, token) -> the state after the unit rules the token reduces there
        self.unit_tops: dict[tuple[int, int, str], int] = {}

    def after_unit_rules(self, below: int, top: int, ttype: str) -> int:
        """The state that replaces ``top`` once the unit rules that ``ttype`` reduces are done (a
        unit rule only changes the top state: the chain depends on the state below and ``ttype``)."""
        key = (below, top, ttype)
        found = self.unit_tops.get(key)
        if found is None:
            found = top
            while True:
                action = self.states[found].get(ttype)
                if action is None or action[0] or action[1][2] is not None:
                    break
                found = self.states[below][action[1][1]][1]
            self.unit_tops[key] = found
        return found


def _passes_through(rule) -> bool:  # noqa: ANN001 - a lark Rule
    return bool(rule.options.expand1 and len(rule.expansion) == 1 and rule.alias is None
                and not rule.expansion[0].name.startswith("_"))


def _continues_repetition(rule) -> bool:  # noqa: ANN001 - a lark Rule
    """``__x_star_N: __x_star_N item...``, the rule that lark makes for each further item of a
    repetition: its callback makes a new Tree of the old one's children plus the items (all of
    them: grammar.lark names every terminal, so none is filtered out)."""
    name = rule.origin.name
    return name.startswith("__") and rule.expansion[0].name == name


def _extend_items(children: list) -> Tree:
    """The callback of a rule that continues a repetition: the same, in place (no Tree copy)."""
    items = children[0]
    items.children += children[1:]
    return items


@cache
def tables() -> Tables:
    return Tables()
