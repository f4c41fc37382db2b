"""Discovery that depends on state, split when it does not fit one fragment (issue 25).

When invariants read state, discovery is one program of the module's own (``RUN_LOCAL``), run
again whenever a value changes; taking a role runs the role's entry items (role state, command
installs, startup statements, behaviours started with ``RUN_LOCAL``) inside it
(``discovery.watched_code``). When that does not fit a fragment, each role keeps in the discovery
program the leading entry items that fit; the rest become a chain of commands installed for
any role (spare command numbers no command of the program uses, distinct for every part) by
fragments injected *before* the discovery fragment, so that on every link they arrive first.
Taking the role then ends with ``EVAL_COMMAND`` of the role's first part; part j runs part j+1.

What is preserved: the items run in their order, once per taking of the role, as before; a
behaviour is still started with ``RUN_LOCAL`` (one copy per module however often the role is
taken); a module that takes another role before the rest has run still runs it (the parts are
installed for any role), as the unsplit program ran the whole entry when it took the role. What
differs: the rest runs a few steps later (a command queued by ``EVAL_COMMAND`` runs on a later
step), and a module left with no role by then drops it (a module without a role runs no user
command).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.discovery import watched_code
from rdcd_core.compiler.entry import EntryItem
from rdcd_core.compiler.exprgen import emit
from rdcd_core.compiler.ir import Body, Item
from rdcd_core.syntax import ast
from vm.isa.opcodes import USER_COMMAND_BASE, USER_COMMANDS
from vm.roles import ANY_ROLE


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
        # for any role: a module that takes another role before the part runs still runs it,
        # as the unsplit program ran the whole entry when it took the role
        emit(code, "INSTALL_COMMAND", ANY_ROLE, self.number, Body(body), span=self.items[0].span)
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
    """(items kept per role, calls, fragments of parts) for a discovery program that fits with
    its parts (each fragment a list of parts, the first with the prologue), or None when it
    cannot be split (too few spare numbers, or the tests alone do not fit). ``fits(code)`` is
    the planner's check of a fragment's code."""
    if not numbers:
        return None
    roles = [ctxs[role] for role in deployment]
    placed = _place(fits, roles, items, numbers[0])
    if placed is None:
        return None
    kept, calls = placed
    free = iter(numbers)
    parts: list[Part] = []
    for role in deployment:
        if role not in calls:
            continue
        chain = _chain(fits, ctxs[role], role, items[role][len(kept[role]):], free)
        if chain is None:
            return None
        calls[role] = chain[0].number
        parts += chain
    return kept, calls, _pack(fits, ctxs, parts, prologue)


def _calls(roles: list[Context], kept: dict[str, list[EntryItem]], items: dict[str, list[EntryItem]],
           first: int) -> dict[str, int]:
    return {ctx.role: first for ctx in roles if len(kept[ctx.role]) < len(items[ctx.role])}


def _place(fits, roles: list[Context], items: dict[str, list[EntryItem]],  # noqa: ANN001
           number: int) -> tuple[dict[str, list[EntryItem]], dict[str, int]] | None:
    """The leading items of each role that fit the discovery program, in deployment order; None
    when not even the tests fit. (Every call is as large: ``number`` stands for all.)"""
    kept: dict[str, list[EntryItem]] = {ctx.role: [] for ctx in roles}
    if not fits(watched_code(roles, kept, [], _calls(roles, kept, items, number))):
        return None
    for ctx in roles:
        for n in range(1, len(items[ctx.role]) + 1):
            trial = {**kept, ctx.role: items[ctx.role][:n]}
            if not fits(watched_code(roles, trial, [], _calls(roles, trial, items, number))):
                break
            kept = trial
    return kept, _calls(roles, kept, items, number)


def _chain(fits, ctx: Context, role: str, rest: list[EntryItem],  # noqa: ANN001
           free: Iterator[int]) -> list[Part] | None:
    """``rest`` as parts that each fit a fragment alone (an item too large alone is a part of its
    own, over the budget), numbered from ``free``; None when the numbers run out."""
    chunks: list[list[EntryItem]] = []
    for item in rest:
        if chunks:
            trial = Part(role, chunks[-1] + [item], 0, 1)
            if fits(install_code({role: ctx}, [trial], [])):
                chunks[-1].append(item)
                continue
        chunks.append([item])
    numbers = [next(free, None) for _ in chunks]
    if None in numbers:
        return None
    return [Part(role, chunk, numbers[j], numbers[j + 1] if j + 1 < len(chunks) else 0)  # type: ignore[arg-type]
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
