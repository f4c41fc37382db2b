"""Commands and behaviours too large for one fragment, as a chain of commands that fit.

A body's top-level statements are cut into parts, each installed by its own entry item: the
first part keeps the method's command number, every further part gets a spare number of the
role's command table. The parts are injected last part first: on every link program packets keep
their order, so when the first part (the one that is started) arrives the others are there. A
command that arrives before its part does is held by the VM until the part is installed
(docs/vm.md).

On the default target a part ends by going on in the next one in the same run
(``CONTINUE_COMMAND``, the argument kept), and the last part ends the run as the body did
(``END_TERMINATE``, ``END_REPEAT``, ``END_WAIT``: a behaviour runs again from its first part): the
chain is the unsplit body, run for run; handlers (``handlers``) and state-dependent discovery
(``watched``) go on the same way. On a target without it (``original``) a part runs the next one
as a run of its own (``EVAL_COMMAND next``, with the argument from the stack when the rest reads
it), and the last part of a behaviour runs the first again; between two parts other tasks may
run, as between two runs of a behaviour. What is not split: a statement alone too large for a
fragment (W601 names it), code re-checked as values change (``watched``: its entry items are
split there), there a reactive behaviour (``END_WAIT``), and a part that needs the argument on a
target without ``EVAL_COMMAND_STACK_ARG``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.entry import EntryItem, behaviour_numbers
from rdcd_core.compiler.exprgen import emit
from rdcd_core.compiler.ir import Body, Item, Label
from rdcd_core.compiler.stmtgen import statements
from rdcd_core.semantics.model import Model
from rdcd_core.syntax import ast
from vm.isa.opcodes import USER_COMMAND_BASE, USER_COMMANDS

Fits = Callable[[EntryItem], bool]


@dataclass(slots=True)
class Spares:
    """Command numbers no command or behaviour of the program uses, handed to chain parts. A
    number given to a part of role R is not given to a role related to R (an install for R also
    fills the tables of R's sub-roles)."""

    model: Model
    free: list[int]
    taken: dict[str, set[int]] = field(default_factory=dict)

    def take(self, role: str) -> int | None:
        related = {r for r in self.taken
                   if r == role or self.model.is_subrole(r, role) or self.model.is_subrole(role, r)}
        used = set().union(*(self.taken[r] for r in related)) if related else set()
        number = next((k for k in self.free if k not in used), None)
        if number is not None:
            self.taken.setdefault(role, set()).add(number)
        return number

    def give_back(self, role: str, number: int) -> None:
        self.taken.get(role, set()).discard(number)


def spare_numbers(model: Model, commands: dict[str, int]) -> Spares:
    used = set(commands.values())
    for role in model.deployment:
        used |= set(behaviour_numbers(model, role, commands).values())
    return Spares(model, [k for k in range(USER_COMMANDS) if k not in used])


@dataclass(slots=True)
class Culprit:
    """Why a method was not split: the statement that does not fit alone (None: not splittable)."""

    stmt: ast.Stmt | None


def split_method(item: EntryItem, ctx: Context, spares: Spares,
                 fits: Fits) -> tuple[list[EntryItem], dict[int, ast.Stmt]] | Culprit:
    """``item`` (a command or behaviour that does not fit a fragment alone) as a chain of items,
    last part first, with the statements that alone do not fit (by id of the item holding one:
    it is over the budget); a ``Culprit`` when it cannot be split."""
    method = item.symbol
    if method is None or item.kind not in ("command", "behavior") or ctx.watched:
        return Culprit(None)
    stmts = _flat(list(method.decl.body.statements))
    if item.kind == "behavior" and item.reactive and not ctx.has("CONTINUE_COMMAND"):
        return Culprit(None)  # END_WAIT re-runs the part that ends the run: only a continuation keeps it
    if len(stmts) < 2:
        return Culprit(stmts[0] if stmts else None)
    params = method.decl.params
    argument = params[0].text if params and item.kind == "command" else None
    reads = [False] * (len(stmts) + 1)  # reads[i]: statements i.. read the command's argument
    for i in range(len(stmts) - 1, -1, -1):
        reads[i] = reads[i + 1] or _reads([stmts[i]], argument)
    parts: list[list[ast.Stmt]] = []
    alone: list[int] = []  # indexes of parts that are one statement too large for a fragment
    rest = stmts
    taken: list[int] = []
    while rest:
        first = not parts
        if len(parts) > len(spares.free):  # more parts than numbers: do not even try
            return _give_back(spares, ctx.role, taken)
        # the longest run of statements that fits, grown one statement at a time (a part is
        # small, so this stays linear in the body); the first part alone is the unsplit body
        limit = len(rest) - 1 if first else len(rest)
        k = 0
        while k < limit:
            at = len(stmts) - len(rest) + k + 1  # where the rest after this trial starts
            trial = _part_item(item, ctx, rest[:k + 1], first, k + 1 < len(rest), 0, 0, reads[at])
            if trial is None or not fits(trial):
                break
            k += 1
        if k == 0:  # this statement does not fit alone: a part of its own, over the budget
            at = len(stmts) - len(rest) + 1
            if _part_item(item, ctx, rest[:1], first, len(rest) > 1, 0, 0, reads[at]) is None:
                return _give_back(spares, ctx.role, taken)
            alone.append(len(parts))
            k = 1
        parts.append(rest[:k])
        rest = rest[k:]
        if rest:
            number = spares.take(ctx.role)
            if number is None:
                return _give_back(spares, ctx.role, taken)
            taken.append(number)
    numbers = [item.number, *(USER_COMMAND_BASE + n for n in taken)]
    items = []
    culprits: dict[int, ast.Stmt] = {}
    at = 0
    for index, part in enumerate(parts):
        more = index + 1 < len(parts)
        following = numbers[index + 1] if more else numbers[0]
        at += len(part)
        made = _part_item(item, ctx, part, index == 0, more, numbers[index], following, reads[at])
        assert made is not None  # it was made for the trial
        items.append(made)
        if index in alone:
            culprits[id(made)] = part[0]
    return list(reversed(items)), culprits


def _give_back(spares: Spares, role: str, taken: list[int]) -> Culprit:
    for number in taken:
        spares.give_back(role, number)
    return Culprit(None)


def _flat(stmts: list[ast.Stmt]) -> list[ast.Stmt]:
    """A body's statements with plain nested blocks opened (their statements run in order)."""
    result: list[ast.Stmt] = []
    for stmt in stmts:
        if isinstance(stmt, ast.Block):
            result += _flat(list(stmt.statements))
        else:
            result.append(stmt)
    return result


def _reads(stmts: list[ast.Stmt], name: str | None) -> bool:
    return name is not None and any(isinstance(node, ast.NameRef) and node.name.text == name
                                    for stmt in stmts for node in ast.walk(stmt))


def _part_item(item: EntryItem, ctx: Context, part: list[ast.Stmt], first: bool, more: bool,
               number: int, following: int, rest_reads: bool) -> EntryItem | None:
    """The entry item installing ``part`` as command ``number``, then running ``following`` (with
    the argument when the statements after the part read it: ``rest_reads``); None if the target
    cannot pass the argument on."""
    method = item.symbol
    assert method is not None
    params = method.decl.params
    argument = params[0].text if params and item.kind == "command" else None
    saved = ctx.argument, ctx.in_body
    ctx.argument, ctx.in_body = argument, True
    if item.mixin:
        ctx.mixins.append(item.mixin)
    try:
        body: list[Item] = []
        end = Label("repeat")
        if first and item.check:
            emit(body, "HAS_ROLE", item.install_role, span=method.decl.name.span)
            emit(body, "IF_FALSE_GOTO", end, span=method.decl.name.span)
        statements(part, ctx, body)
        span = part[-1].span
        rest_reads = rest_reads and more
        repeat = "END_WAIT" if item.reactive else "END_REPEAT"
        if ctx.has("CONTINUE_COMMAND"):  # the same run goes on in the next part, its argument kept
            if more:
                emit(body, "CONTINUE_COMMAND", following, span=span)
            else:  # the end of the run: a behaviour runs again from its first part
                emit(body, repeat if item.kind == "behavior" else "END_TERMINATE", span=span)
        else:
            if item.kind == "behavior" or more:
                if rest_reads:
                    if not ctx.has("EVAL_COMMAND_STACK_ARG"):
                        return None
                    emit(body, "PUSH_ARGUMENT", 0, span=span)
                    emit(body, "EVAL_COMMAND_STACK_ARG", following, span=span)
                else:
                    emit(body, "EVAL_COMMAND", following, 0, span=span)
            emit(body, "END_TERMINATE", span=span)
        if first and item.check:
            body.append(end)
            emit(body, repeat, span=method.decl.span)
    finally:
        ctx.argument, ctx.in_body = saved
        if item.mixin:
            ctx.mixins.pop()
    code: list[Item] = []
    emit(code, "INSTALL_COMMAND", item.install_role, number, Body(body), span=method.decl.name.span)
    if first and item.kind == "behavior":
        emit(code, "EVAL_COMMAND", number, 0, span=method.decl.name.span)
    span = part[0].span.cover(part[-1].span)
    return EntryItem(item.kind, code, span, item.method)


__all__ = ["Culprit", "Spares", "spare_numbers", "split_method"]
