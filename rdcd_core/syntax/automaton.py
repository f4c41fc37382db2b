"""Running the LALR automaton outside the main loop: trial parses and forced steps for recovery.

A stack is a list of LALR states; the value stack beside it holds what the driver shifted and
reduced. Rows are ``{symbol: (True, next state) | (False, (size, nonterminal, callback))}``.
"""

from __future__ import annotations

from rdcd_core.syntax import ast
from rdcd_core.syntax.lexer import Tok
from rdcd_core.syntax.tables import Tables


def progress(t: Tables, stack: list, types: list[str], limit: int | None = None) -> int:
    """How many of ``types`` the automaton ``stack[:limit]`` shifts before an error (all: len).

    The stack is never copied (it can be deep): states pushed during the trial go to ``over``,
    and reductions below them lower ``base``.
    """
    states = t.states
    end_state = t.end_state
    base = len(stack) if limit is None else limit
    over: list = []
    for count, ttype in enumerate(types):
        while True:
            action = states[over[-1] if over else stack[base - 1]].get(ttype)
            if action is None:
                return count
            if action[0]:
                over.append(action[1])
                break
            size, origin, _ = action[1]
            if size >= len(over):
                base -= size - len(over)
                over.clear()
            elif size:
                del over[-size:]
            over.append(states[over[-1] if over else stack[base - 1]][origin][1])
            if ttype == "$END" and over[-1] == end_state:
                return len(types)
    return len(types)


def accepts(t: Tables, stack: list, types: list[str], limit: int | None = None) -> bool:
    """Whether the automaton ``stack[:limit]`` can shift all of ``types`` (or accept at $END)."""
    return progress(t, stack, types, limit) == len(types)


def expected(t: Tables, stack: list) -> set[str]:
    """The terminals the automaton can shift next."""
    return {name for name in (*t.terminals, "$END") if accepts(t, stack, [name])}


def _reduce(t: Tables, stack: list, values: list, arg: tuple) -> None:
    size, origin, callback = arg
    states = t.states
    if callback is None:  # a unit rule
        stack[-1] = states[stack[-2]][origin][1]
        return
    children = values[-size:] if size else []
    if size:
        del stack[-size:]
        del values[-size:]
    values.append(callback(children))
    stack.append(states[stack[-1]][origin][1])


def feed(t: Tables, stack: list, values: list, tok: Tok) -> None:
    """Shifts ``tok`` (a token made up by the recovery), reducing first as needed."""
    states = t.states
    while True:
        action = states[stack[-1]].get(tok.type)
        if action is None:
            return
        if action[0]:
            stack.append(action[1])
            values.append(tok)
            return
        _reduce(t, stack, values, action[1])


def reduce_deployment(t: Tables, stack: list, values: list) -> bool:
    """After a complete ``deployment { … }``, reduces it to a ``Deployment`` on top of ``values``."""
    if not (values and isinstance(values[-1], Tok) and values[-1].type == "RBRACE"):
        return False
    if not accepts(t, stack, ["$END"]):
        return False
    for _ in range(8):
        if isinstance(values[-1], ast.Deployment):
            return True
        action = t.states[stack[-1]].get("$END")
        if action is None or action[0] or action[1][1] == "start":
            return False
        _reduce(t, stack, values, action[1])
    return False
