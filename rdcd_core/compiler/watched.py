"""Discovery that depends on state, split when it does not fit one fragment (issue 25).

When invariants read state, discovery is one program of the module's own (``RUN_LOCAL``), run
again whenever a value changes (``END_WAIT``); taking a role runs the role's entry items (role
state, command installs, startup statements, behaviours started with ``RUN_LOCAL``) inside it
(``discovery.watched_code``). When that does not fit a fragment:

- the roles are cut into groups in deployment order: the discovery program tests the first
  group; when none of its roles holds, its run goes on (``CONTINUE_COMMAND``) in a command that
  tests the next group, and so on; the last group ends as the unsplit program (no role);
- each role keeps in its group's code the leading entry items that fit; its run goes on in a
  chain of commands with the rest, the last ending the run (``END_WAIT``).

The commands take spare command numbers (no command of the program uses them) and are installed
by fragments injected *before* the discovery fragment, so that on every link they arrive first:
the tests of later roles for any role, none included (each its own number), the rest of a role's
entry for that role (unrelated roles may share a number). ``CONTINUE_COMMAND`` goes on in
another code in the same run, with the same argument: the split program tests the same roles in the same order
and runs the same entry items in the same run as the unsplit one; a run only counts a few more
instructions (the continuations).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.discovery import invariants, recheck_code, watched_code
from rdcd_core.compiler.entry import EntryItem
from rdcd_core.compiler.exprgen import emit
from rdcd_core.compiler.ir import Body, Item
from rdcd_core.semantics.model import Model
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from vm.isa.opcodes import USER_COMMAND_BASE, USER_COMMANDS
from vm.roles import ANY_ROLE


@dataclass(slots=True)
class Part:
    """Code run by command ``number``, installed for any role: entry items of ``role`` (then
    command ``following``, 0: none), or ``recheck``, the tests of roles deployed later."""

    role: str
    items: list[EntryItem]
    number: int
    following: int = 0
    recheck: list[Item] | None = None
    where: Span | None = None  # the source it comes from, when it has no items
    install: int = ANY_ROLE  # the role id it is installed for

    @property
    def span(self) -> Span:
        if self.items:
            return self.items[0].span.cover(self.items[-1].span)
        assert self.where is not None
        return self.where

    def code(self) -> list[Item]:
        body: list[Item] = []
        if self.recheck is not None:
            body = list(self.recheck)
        else:
            for item in self.items:
                body.extend(item.code)
            if self.following:
                emit(body, "CONTINUE_COMMAND", self.following, span=self.span)
            else:  # the end of the discovery program's run
                emit(body, "END_WAIT", span=self.span)
        code: list[Item] = []
        # the tests of later roles for any role, none included (they run on a module that has
        # none); the rest of a role's entry for the role (it runs once the module has taken it)
        emit(code, "INSTALL_COMMAND", self.install, self.number, Body(body), span=self.span)
        return code


def watched_numbers(commands: dict[str, int]) -> list[int]:
    """Command numbers (128 + k) no command of the program uses: behaviours of state-dependent
    discovery run with ``RUN_LOCAL``, not from the command table."""
    used = set(commands.values())
    return [USER_COMMAND_BASE + k for k in range(USER_COMMANDS) if k not in used]


def install_code(parts: list[Part], prologue: list[Item]) -> list[Item]:
    """A fragment that installs ``parts`` on every module and migrates."""
    out: list[Item] = list(prologue)
    for part in parts:
        out.extend(part.code())
    emit(out, "MIGRATE_CONTINUE", span=parts[0].span)
    return out


@dataclass(slots=True)
class Split:
    kept: dict[str, list[EntryItem]]  # the entry items the discovery program runs, per role
    calls: dict[str, int]  # the command that runs the rest of a role's entry
    tail: int  # the command that tests the roles after the discovery program's (0: none)
    roles: list[str]  # the roles the discovery program tests
    fragments: list[list[Part]]  # install fragments, injected first (the first with the prologue)


def split_watched(fits, ctxs: dict[str, Context], deployment: list[str],  # noqa: ANN001
                  items: dict[str, list[EntryItem]], prologue: list[Item],
                  numbers: list[int]) -> Split | None:
    """The discovery program that fits, with its parts; None when it cannot be split (too few
    spare numbers, or one role's tests alone do not fit). ``fits(code)`` is the planner's check
    of a fragment's code."""
    if not numbers:
        return None
    free = _Numbers(numbers, ctxs[deployment[0]].model)
    roles = [ctxs[role] for role in deployment]
    parts: list[Part] = []
    first: Split | None = None
    previous = 0  # the number of the group before (its tail)
    start = 0
    while start < len(roles):
        is_first = start == 0
        end = start + 1
        while end < len(roles) and invariants(roles[end - 1]) and fits(_group_code(
                roles[start:end + 1], {}, _calls(roles[start:end + 1], {}, items, numbers[0]),
                numbers[0] if end + 1 < len(roles) else 0, deployment, is_first, numbers[0])):
            end += 1
        group = roles[start:end]
        more = end < len(roles) and bool(invariants(group[-1]))
        tail = numbers[0] if more else 0
        kept = _place(fits, group, items, deployment, is_first, tail, numbers[0])
        if kept is None:
            return None
        tail = free.take(None) if more else 0
        if more and not tail:
            return None
        calls = _calls(group, kept, items, numbers[0])
        for ctx in group:
            if ctx.role in calls:
                chain = _chain(fits, ctx, items[ctx.role][len(kept[ctx.role]):], free)
                if chain is None:
                    return None
                calls[ctx.role] = chain[0].number
                parts += chain
        if is_first:
            first = Split(kept, calls, tail, [ctx.role for ctx in group], [])
        else:
            recheck = recheck_code(group, kept, deployment, calls, tail)
            span = group[0].model.roles[group[0].role].decl.name.span
            parts.append(Part(group[0].role, [i for ctx in group for i in kept[ctx.role]], previous,
                              recheck=recheck, where=span))
        previous = tail
        start = end if more else len(roles)
    assert first is not None
    first.fragments = _pack(fits, parts, prologue)
    return first


def _group_code(group: list[Context], kept: dict[str, list[EntryItem]], calls: dict[str, int], tail: int,
                deployment: list[str], is_first: bool, number: int) -> list[Item]:
    """The code of a group's fragment: the discovery program, or the install of a later group's
    tests (``number`` stands for its command number: every number is one byte)."""
    if is_first:
        return watched_code(group, kept, [], calls, tail)
    recheck = recheck_code(group, kept, deployment, calls, tail)
    span = group[0].model.roles[group[0].role].decl.name.span
    return install_code([Part(group[0].role, [], number, recheck=recheck, where=span)], [])


def _calls(roles: list[Context], kept: dict[str, list[EntryItem]], items: dict[str, list[EntryItem]],
           first: int) -> dict[str, int]:
    return {ctx.role: first for ctx in roles if len(kept.get(ctx.role, [])) < len(items[ctx.role])}


def _place(fits, group: list[Context], items: dict[str, list[EntryItem]], deployment: list[str],  # noqa: ANN001
           is_first: bool, tail: int, number: int) -> dict[str, list[EntryItem]] | None:
    """The leading items of each role of ``group`` that fit its fragment, in deployment order;
    None when not even the tests fit. (Every call is as large: ``number`` stands for all.)"""
    kept: dict[str, list[EntryItem]] = {ctx.role: [] for ctx in group}

    def code(trial: dict[str, list[EntryItem]]) -> list[Item]:
        calls = _calls(group, trial, items, number)
        return _group_code(group, trial, calls, tail, deployment, is_first, number)

    if not fits(code(kept)):
        return None
    for ctx in group:
        for n in range(1, len(items[ctx.role]) + 1):
            trial = {**kept, ctx.role: items[ctx.role][:n]}
            if not fits(code(trial)):
                break
            kept = trial
    return kept


@dataclass(slots=True)
class _Numbers:
    """Spare command numbers: one installed for any role is used by no other part; one for a role
    by no part of a related role (an install for a role fills its sub-roles' tables too)."""

    free: list[int]
    model: Model
    anywhere: set[int] = field(default_factory=set)
    by_role: dict[str, set[int]] = field(default_factory=dict)

    def take(self, role: str | None) -> int:
        """A number (0: none left) for the tests of later roles (``role`` None) or a role's part."""
        if role is None:
            used = self.anywhere.union(*self.by_role.values())
        else:
            related = [r for r in self.by_role
                       if r == role or self.model.is_subrole(r, role) or self.model.is_subrole(role, r)]
            used = self.anywhere.union(*(self.by_role[r] for r in related))
        number = next((n for n in self.free if n not in used), 0)
        if number:
            (self.anywhere if role is None else self.by_role.setdefault(role, set())).add(number)
        return number


def _chain(fits, ctx: Context, rest: list[EntryItem], free: _Numbers) -> list[Part] | None:  # noqa: ANN001
    """``rest`` as parts that each fit a fragment alone (an item too large alone is a part of its
    own, over the budget), installed for the role; None when the numbers run out."""
    role, role_id = ctx.role, ctx.table.id_of(ctx.role) or 0
    chunks: list[list[EntryItem]] = []
    for item in rest:
        if chunks:
            trial = Part(role, chunks[-1] + [item], 0, 1, install=role_id)
            if fits(install_code([trial], [])):
                chunks[-1].append(item)
                continue
        chunks.append([item])
    numbers = [free.take(role) for _ in chunks]
    if 0 in numbers:
        return None
    return [Part(role, chunk, numbers[j], numbers[j + 1] if j + 1 < len(chunks) else 0, install=role_id)
            for j, chunk in enumerate(chunks)]


def _pack(fits, parts: list[Part], prologue: list[Item]) -> list[list[Part]]:  # noqa: ANN001
    """First fit of the parts into install fragments; the first carries the prologue."""
    fragments: list[list[Part]] = []
    for part in parts:
        for index, fragment in enumerate(fragments):
            if fits(install_code(fragment + [part], prologue if index == 0 else [])):
                fragment.append(part)
                break
        else:
            fragments.append([part])
    return fragments


def culprit(parts: list[Part]) -> ast.Stmt | None:
    """The statement to name when a fragment of one part of one item is over the budget."""
    if len(parts) == 1 and len(parts[0].items) == 1 and parts[0].recheck is None:
        return parts[0].items[0].stmt
    return None


__all__ = ["Part", "Split", "culprit", "install_code", "split_watched", "watched_numbers"]
