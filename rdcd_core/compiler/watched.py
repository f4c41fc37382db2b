"""Discovery that depends on state, split when it does not fit one fragment (issue 25).

When invariants read state, discovery is one program of the module's own (``RUN_LOCAL``), run
again whenever a value changes; taking a role runs the role's entry items (role state, command
installs, startup statements, behaviours started with ``RUN_LOCAL``) inside it
(``discovery.watched_code``). When that does not fit a fragment, each role keeps in the discovery
program the leading entry items that fit; the rest become a chain of commands installed for the
role (spare command numbers, the same numbers for every role: part j of every role is command
K_j) by fragments injected *before* the discovery fragment, so that on every link they arrive
first. Taking the role then ends with ``EVAL_COMMAND K_1``; part j runs part j+1.

What is preserved: the items run in their order, once per taking of the role, as before; a
behaviour is still started with ``RUN_LOCAL`` (one copy per module whatever the number of times
the role is taken). What differs: the rest runs a few steps later (a command queued by
``EVAL_COMMAND`` runs on a later step), and a module that takes another role (or none) before the
rest has run drops it (``CLEAR_COMMAND_QUEUE K_j`` before every ``SET_ROLE_NOTIFY``): the rest of
the earlier role's entry does not run for a role the module no longer plays, where the unsplit
program ran it and then, for behaviours, idled on their role check.
"""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.discovery import watched_code
from rdcd_core.compiler.entry import EntryItem
from rdcd_core.compiler.exprgen import emit
from rdcd_core.compiler.ir import Body, Item
from rdcd_core.syntax import ast
from vm.isa.opcodes import USER_COMMAND_BASE, USER_COMMANDS


@dataclass(slots=True)
class Part:
    """Entry items of one role run by command ``number``, then command ``following`` (0: none)."""

    role: str
    items: list[EntryItem]
    number: int
    following: int = 0

    def code(self, ctx: Context) -> list[Item]:
        body: list[Item] = []
        for item in self.items:
            body.extend(item.code)
        span = self.items[-1].span
        if self.following:
            emit(body, "EVAL_COMMAND", self.following, 0, span=span)
        emit(body, "END_TERMINATE", span=span)
        code: list[Item] = []
        emit(code, "INSTALL_COMMAND", ctx.table.id_of(self.role) or 0, self.number, Body(body),
             span=self.items[0].span)
        return code


def watched_numbers(commands: dict[str, int]) -> list[int]:
    """Command numbers (128 + k) no command of the program uses: behaviours of state-dependent
    discovery run with ``RUN_LOCAL``, not from the command table."""
    used = set(commands.values())
    return [USER_COMMAND_BASE + k for k in range(USER_COMMANDS) if k not in used]


def install_code(ctxs: dict[str, Context], parts: list[Part], prologue: list[Item]) -> list[Item]:
    """A fragment that installs ``parts`` on every module and migrates."""
    out: list[Item] = list(prologue)
    for part in parts:
        out.extend(part.code(ctxs[part.role]))
    span = parts[0].items[0].span
    emit(out, "MIGRATE_CONTINUE", span=span)
    return out


def split_watched(fits, ctxs: dict[str, Context], deployment: list[str],  # noqa: ANN001
                  items: dict[str, list[EntryItem]], prologue: list[Item], numbers: list[int]):
    """(items kept per role, calls, clears, fragments of parts) for a discovery program that fits
    with its parts (each fragment a list of parts, the first with the prologue), or None when it
    cannot be split (no spare number, or the tests alone do not fit). ``fits(code)`` is the
    planner's check of a fragment's code."""
    roles = [ctxs[role] for role in deployment]
    for count in range(1, len(numbers) + 1):  # the numbers every branch must clear
        clears = tuple(numbers[:count])
        placed = _place(fits, roles, items, clears)
        if placed is None:
            return None
        kept, calls = placed
        rest = {role: items[role][len(kept[role]):] for role in deployment if role in calls}
        chains = {role: _chain(fits, ctxs[role], role, rest_items, clears)
                  for role, rest_items in rest.items()}
        if any(chain is None for chain in chains.values()):
            continue  # a role needs more numbers than cleared so far
        parts = [part for chain in chains.values() for part in chain]  # type: ignore[union-attr]
        return kept, calls, clears, _pack(fits, ctxs, parts, prologue)
    return None


def _calls(roles: list[Context], kept: dict[str, list[EntryItem]], items: dict[str, list[EntryItem]],
           first: int) -> dict[str, int]:
    return {ctx.role: first for ctx in roles if len(kept[ctx.role]) < len(items[ctx.role])}


def _place(fits, roles: list[Context], items: dict[str, list[EntryItem]],  # noqa: ANN001
           clears: tuple[int, ...]) -> tuple[dict[str, list[EntryItem]], dict[str, int]] | None:
    """The leading items of each role that fit the discovery program, in deployment order; None
    when not even the tests fit."""
    kept: dict[str, list[EntryItem]] = {ctx.role: [] for ctx in roles}
    if not fits(watched_code(roles, kept, [], _calls(roles, kept, items, clears[0]), clears)):
        return None
    for ctx in roles:
        for n in range(1, len(items[ctx.role]) + 1):
            trial = {**kept, ctx.role: items[ctx.role][:n]}
            if not fits(watched_code(roles, trial, [], _calls(roles, trial, items, clears[0]), clears)):
                break
            kept = trial
    return kept, _calls(roles, kept, items, clears[0])


def _chain(fits, ctx: Context, role: str, rest: list[EntryItem],  # noqa: ANN001
           numbers: tuple[int, ...]) -> list[Part] | None:
    """``rest`` as parts that each fit a fragment alone (an item too large alone is a part of its
    own, over the budget); None when it needs more than ``numbers``."""
    chunks: list[list[EntryItem]] = []
    for item in rest:
        if chunks:
            trial = Part(role, chunks[-1] + [item], 0, 1)
            if fits(install_code({role: ctx}, [trial], [])):
                chunks[-1].append(item)
                continue
        chunks.append([item])
    if len(chunks) > len(numbers):
        return None
    return [Part(role, chunk, numbers[j], numbers[j + 1] if j + 1 < len(chunks) else 0)
            for j, chunk in enumerate(chunks)]


def _pack(fits, ctxs: dict[str, Context], parts: list[Part],  # noqa: ANN001
          prologue: list[Item]) -> list[list[Part]]:
    """First fit of the parts into install fragments; the first carries the prologue."""
    fragments: list[list[Part]] = []
    for part in parts:
        for index, fragment in enumerate(fragments):
            if fits(install_code(ctxs, fragment + [part], prologue if index == 0 else [])):
                fragment.append(part)
                break
        else:
            fragments.append([part])
    return fragments


def culprit(parts: list[Part]) -> ast.Stmt | None:
    """The statement to name when a fragment of one part of one item is over the budget."""
    if len(parts) == 1 and len(parts[0].items) == 1:
        return parts[0].items[0].stmt
    return None


__all__ = ["Part", "culprit", "install_code", "split_watched", "watched_numbers"]
