"""Hover on what state brings: states, parameters and the keywords ``neighbours``, ``children``
and ``state`` (which have no reference, being keywords)."""

from __future__ import annotations

import re

from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.states import assigning_methods, parameter_info, signature_text, state_symbol
from rdcd_core.semantics.model import RoleKind
from rdcd_core.sequences.check import steps_of
from rdcd_core.sequences.progress import done_value, is_rollback, rolled_back_value, undo_value
from rdcd_core.source import Span
from rdcd_core.syntax import ast

KEYWORD_DOCS = {
    "neighbours": (
        "**neighbours** — the values of a module state that this module's neighbours published\n\n"
        "- `neighbours.s`: from every neighbour\n"
        "- `neighbours(DOWN).s`: from the neighbours on the connectors facing a direction\n"
        "- `neighbours(3).s`: from the neighbour on connector 3 (0..7)\n\n"
        "Only as the argument of `min`, `max`, `count` or `sum`, and only for module state: "
        "a neighbour publishes its value on every change. A behaviour that reads it runs again "
        "when a value changes."),
    "children": (
        "**children** — the values of a module state that this module's children published: "
        "the neighbours whose parent in the structure's tree (rooted at the module where the "
        "program entered) is this module.\n\n"
        "`children.s`, only as the argument of `min`, `max`, `count` or `sum`, e.g. "
        "`sum(children.size)`."),
    "state": (
        "**state** `s := value;` — a variable of the module (an int, -128..127, arithmetic "
        "saturates).\n\n"
        "- at the top level: **module state**, kept across role changes; neighbours can read it "
        "(`neighbours.s`)\n"
        "- in a role: **role state**, back to its initial value whenever the module takes the "
        "role or a sub-role\n\n"
        "Assign it with `s := expression;`."),
    "travelling": (
        "**travelling** `state s := value;` — module state whose value travels with the program: "
        "each module it reaches first takes the value it brought, and the program's first fragment "
        "may change it before it moves on (e.g. a hop count)."),
}
WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def keyword_hover(analysis: Analysis, offset: int) -> tuple[str, Span] | None:
    """``neighbours``, ``children`` and ``state``: keywords, so they have no reference."""
    text = analysis.text
    start = max(0, min(offset, len(text)))
    while start > 0 and WORD.match(text[start - 1]):
        start -= 1
    match = WORD.match(text, start)
    if match is None or match.group(0) not in KEYWORD_DOCS or match.end() < offset:
        return None
    if not _is_keyword_token(analysis, match.start(), match.end()):
        return None  # inside a comment
    return KEYWORD_DOCS[match.group(0)], Span(match.start(), match.end())


def _is_keyword_token(analysis: Analysis, start: int, end: int) -> bool:
    from rdcd_core.syntax.tables import tables

    starts = analysis.cache.get("keyword_starts")
    if starts is None:
        lexer = tables().lexer
        try:
            lexed = lexer.lex(analysis.text)
        except Exception:  # hover must never fail on broken text
            return False
        starts = {(t.start, t.end) for t in lexed.tokens if t.value in KEYWORD_DOCS}
        analysis.cache["keyword_starts"] = starts
    return (start, end) in starts


def state_hover(analysis: Analysis, target: str) -> str | None:
    model = analysis.model
    assert model is not None
    symbol = state_symbol(model, target)
    if symbol is None:
        return None
    name = symbol.name
    sequence = next((q for q in analysis.program.sequences if q.name.text == name), None) \
        if analysis.program is not None and symbol.owner is None else None
    if sequence is not None and not any(d.name.text == name for d in analysis.program.states):
        return progress_hover(sequence)
    if symbol.owner is None and symbol.travelling:
        lines = [f"**travelling state** `{name}` := {symbol.initial}", "",
                 f"module state whose value travels with the program: {symbol.initial} where it enters; "
                 "on every other module, the value the program brought from the neighbour that first "
                 "sent it, as the code of the program's first fragment left it"]
    elif symbol.owner is None:
        lines = [f"**module state** `{name}` := {symbol.initial}", "",
                 f"kept across role changes; {symbol.initial} when the program starts on the module"]
    else:
        family = ", ".join(f"`{r}`" for r in model.subroles(symbol.owner) if r != symbol.owner)
        owner = model.roles.get(symbol.owner)
        if owner is not None and owner.kind is RoleKind.ABSTRACT:  # never taken itself
            takes = f"a role that extends `{symbol.owner}`" + (f" ({family})" if family else "")
        else:
            takes = f"`{symbol.owner}`" + (f" or a sub-role ({family})" if family else "")
        lines = [f"**role state** `{name}` := {symbol.initial} of role `{symbol.owner}`", "",
                 f"back to {symbol.initial} whenever the module takes {takes}; inside "
                 "`self.assumeRole(M, …)` the module keeps its role's state"]
    if symbol.published:
        lines.append(f"published: neighbours read it (`neighbours.{name}`, `children.{name}`), "
                     "so every change is sent to them")
    elif symbol.owner is None:
        lines.append("not published: no neighbour reads it")
    writers = assigning_methods(analysis, target)
    lines.append("assigned in: " + (", ".join(f"`{w}()`" for w in writers) if writers else "nowhere"))
    if symbol.index >= 0:
        lines.append(f"byte {symbol.index} of the module's state memory")
    return "\n".join(lines)


def progress_hover(sequence: ast.Sequence) -> str:
    """The progress state a sequence declares (rdcd_core/sequences/lower.py): what its values
    mean, as docs/reconfiguration.md "How it runs" and "Rolling back from a program" say."""
    name = sequence.name.text
    n = sum(1 for _ in steps_of(sequence))
    done = done_value(sequence)
    lines = [f"**progress** of sequence `{name}` := 0", "",
             f"the number of steps done: 0 before the first, {done} when the sequence is done "
             "(the steps of a parallel block are counted one by one)"]
    if is_rollback(sequence) and n:
        undos = ("" if n < 2 else f"{undo_value(n, 0)} says to undo step 1, " if n == 2 else
                 f"{undo_value(n, n - 2)}..{undo_value(n, 0)} say which step to undo next "
                 f"({undo_value(n, n - 2)}: step {n - 1}, {undo_value(n, 0)}: step 1), ")
        lines.append(f"rolling back (`rollback`, after a step failed): {undos}"
                     f"{rolled_back_value(n)}: rolled back")
    lines.append(f"module state, published: every module takes the furthest value it hears of "
                 f"(`max(neighbours.{name})`), and only the module of the next step moves it on")
    lines.append(f"run backwards (`--reverse-sequence {name}`), the same values count the undos")
    return "\n".join(lines)


def parameter_hover(analysis: Analysis, target: str) -> str | None:
    model = analysis.model
    assert model is not None
    info = parameter_info(model, target)
    if info is None:
        return None
    kind = info.method.kind
    where = f"`{info.role}.{signature_text(info.method)}`"
    if kind == "command":
        lines = [f"**parameter** `{info.name.text}`: int of command {where}", "",
                 f"the argument of `{info.role}.{info.method.name.text}(value)`, carried in the "
                 "command packet's argument byte"]
    else:
        lines = [f"**parameter** `{info.name.text}`: int of method {where}", "",
                 f"argument {info.index + 1} of `self.{info.method.name.text}(…)`; each call "
                 "substitutes its argument (a method is inlined)"]
    lines.append("not available in event handlers (they run later): copy it into a state")
    return "\n".join(lines)
