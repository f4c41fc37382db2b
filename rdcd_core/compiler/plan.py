"""Fragments and the injection plan: group sibling discoveries, place each role's entry items in
its discovery fragment while it fits the budget, split the rest into continuation fragments.

Injection order = deployment order; for each group its discovery fragment, then its
continuations. A role whose invariants observe neighbour roles is discovered by a fragment
injected after the fragments that announce those roles; the injector must space injections so
that a fragment has diffused (and its notifications arrived) before the next one is injected.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.chain import Culprit, Spares, split_method
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.discovery import (
    common_prefix,
    continuation_code,
    group_code,
    observes_roles,
    reads_state,
    watched_code,
)
from rdcd_core.compiler.early import Traffic, traffic_of
from rdcd_core.compiler.entry import EntryItem, entry_items, split_statement, startup_items
from rdcd_core.compiler.handlers import HandlerSplitter
from rdcd_core.compiler.ir import Item
from rdcd_core.compiler.layout import assemble, laid_out_size, size_bound
from rdcd_core.compiler.peephole import optimise
from rdcd_core.compiler.priority import Guard, earlier_overlapping
from rdcd_core.compiler.program import MAX_PROGRAM_BYTES, Fragment
from rdcd_core.compiler.watched import culprit as watched_culprit
from rdcd_core.compiler.watched import install_code, split_watched, watched_numbers
from rdcd_core.source import Span
from rdcd_core.syntax import ast

# what an over-budget fragment means on the robot (and in both worlds, which enforce the limit)
_NOT_RECEIVED = ("the robot would not receive it (a packet over the IR limit is not sent; the "
                 "simulator does not send it either);")

# What a trial fragment's code is made of: its kind, its roles and the identities of their entry
# items (alive while planning). Code made twice from one makeup is the same code.
Makeup = tuple


@dataclass(slots=True)
class Planner:
    ctxs: dict[str, Context]
    budget: int  # program bytes
    fragments: list[Fragment] = field(default_factory=list)
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    names: set[str] = field(default_factory=set)  # of the fragments
    suffixes: dict[str, int] = field(default_factory=dict)  # name -> the last suffix taken
    prologue: list[Item] = field(default_factory=list)  # code the first fragment starts with
    trailer: bytes = b""  # what the first fragment ends with: DATA, the value it carries
    deployment: list[str] = field(default_factory=list)
    waiting: set[str] = field(default_factory=set)  # roles whose discovery fragment starts with SLEEP
    spares: Spares | None = None  # command numbers for the parts of split commands (chain)
    # the statement that alone does not fit, of an item that could not be split (by id of the item)
    culprits: dict[int, ast.Stmt] = field(default_factory=dict)
    traffic: list[Traffic] = field(default_factory=list)  # of each fragment: commands sent, installed

    # optimised trial code by what it is made of (``Makeup``): a fragment is added with the code of
    # its last successful trial, made again, and that is not optimised a second time
    optimised: dict[Makeup, list[Item]] = field(default_factory=dict)

    def optimise(self, code: list[Item], makeup: Makeup | None = None) -> list[Item]:
        if makeup is None:
            return optimise(code)
        done = self.optimised.get(makeup)
        if done is None:
            done = self.optimised[makeup] = optimise(code)
        return done

    def guard(self, group: list[str]) -> Guard:
        """Whether the fragment of ``group`` must leave modules that took an earlier deployed role
        alone (``priority``), and wait for that role's fragment."""
        earlier = self.deployment[:self.deployment.index(group[0])] if group[0] in self.deployment else []
        overlapping = {other.role for role in group
                       for other in earlier_overlapping(self.ctxs[role], [self.ctxs[r] for r in earlier])}
        return Guard(bool(overlapping), bool(overlapping & self.waiting))

    def size(self, code: list[Item], makeup: Makeup | None = None) -> int:
        return laid_out_size(self.optimise(code, makeup))

    def fits(self, code: list[Item], makeup: Makeup | None = None) -> bool:
        """``size(code) <= budget``; the bound decides most trials without optimising."""
        return size_bound(code) <= self.budget or self.size(code, makeup) <= self.budget

    def add(self, name: str, kind: str, roles: list[str], code: list[Item], span: Span,
            methods: list[str], makeup: Makeup | None = None, culprit: ast.Stmt | None = None) -> None:
        blob, entries = assemble(self.optimise(code, makeup))
        carried = b""
        if self.trailer and not self.fragments:  # the first fragment carries the travelling value
            carried = self.trailer
            blob += carried
        unique, n = name, self.suffixes.get(name, 1)
        while unique in self.names:  # resumes where the last fragment of this name stopped
            n += 1
            unique = f"{name}_{n}"
        self.suffixes[name] = n
        self.names.add(unique)
        role = roles[0] if len(roles) == 1 else None
        self.fragments.append(Fragment(unique, kind, role, blob, entries, span, roles=list(roles),
                                       methods=list(dict.fromkeys(methods))))
        self.traffic.append(traffic_of(code, {self.ctxs[r].table.id_of(r) or 0 for r in roles}))
        if len(blob) > self.budget + len(carried):
            self._over_budget(unique, len(blob), span, culprit)

    def culprit_of(self, items: list[EntryItem]) -> ast.Stmt | None:
        """The statement to name when a fragment of ``items`` is over the budget: the one of an
        item that could not be split (or the item's own statement, a startup statement)."""
        for item in items:
            stmt = self.culprits.get(id(item), item.stmt)
            if stmt is not None:
                return stmt
        return None

    def _over_budget(self, name: str, size: int, span: Span, culprit: ast.Stmt | None = None) -> None:
        if size > MAX_PROGRAM_BYTES:
            self.diagnostics.append(diag.make(
                codes.FRAGMENT_TOO_LARGE, span,
                f"fragment {name} is {size} bytes, more than the {MAX_PROGRAM_BYTES} bytes of a "
                f"program slot; {_NOT_RECEIVED} split this code into smaller methods or statements"))
        elif culprit is not None:
            self.diagnostics.append(diag.make(
                codes.OVER_BUDGET, culprit.span,
                f"fragment {name} is {size} bytes, over the packet budget of {self.budget} program "
                "bytes, and could not be split: this statement alone does not fit a fragment; "
                f"{_NOT_RECEIVED} simplify it or make it several statements",
                related=(diag.Related(span, "the code the fragment holds"),) if span != culprit.span else ()))
        else:
            self.diagnostics.append(diag.make(
                codes.OVER_BUDGET, span,
                f"fragment {name} is {size} bytes, over the packet budget of {self.budget} program "
                f"bytes, and could not be split; {_NOT_RECEIVED} simplify this code"))


def depends_on(ctx: Context, others: list[str]) -> bool:
    for inv in ctx.model.roles[ctx.role].invariants:
        for node in ast.walk(inv.decl.expr):
            if isinstance(node, ast.FunctionCall) and node.name.text == "connected_role":
                target = ast.unparen(node.args[1]) if len(node.args) == 2 else None
                if isinstance(target, ast.NameRef) and any(
                        ctx.model.is_subrole(o, target.name.text) for o in others):
                    return True
    return False


def can_group(planner: Planner, group: list[str]) -> bool:
    ctxs = [planner.ctxs[r] for r in group]
    model = ctxs[0].model
    if len({model.roles[r].parent for r in group}) != 1:
        return False
    if any(depends_on(ctx, group) for ctx in ctxs):
        return False
    common = common_prefix(ctxs)
    return common > 0 and planner.fits(group_code(ctxs, {}, common, guard=planner.guard(group)))


def form_groups(planner: Planner, deployment: list[str]) -> list[list[str]]:
    groups: list[list[str]] = []
    for role in deployment:
        if groups and can_group(planner, groups[-1] + [role]):
            groups[-1].append(role)
        else:
            groups.append([role])
    return groups


def plan_group(planner: Planner, group: list[str], items: dict[str, list[EntryItem]]) -> None:
    ctxs = [planner.ctxs[r] for r in group]
    common = common_prefix(ctxs) if len(group) > 1 else 0
    guard = planner.guard(group)
    if guard.waits or any(observes_roles(ctx) for ctx in ctxs):
        planner.waiting.update(group)
    placed: dict[str, list[EntryItem]] = {r: [] for r in group}
    rest: dict[str, list[EntryItem]] = {}
    for role in group:
        pending = items[role]
        taken = 0
        while taken < len(pending):
            placed[role].append(pending[taken])
            if not planner.fits(group_code(ctxs, placed, common, planner.prologue, guard),
                                _makeup("discovery", placed)):
                placed[role].pop()
                break
            taken += 1
        rest[role] = pending[taken:]
    model = ctxs[0].model
    span = model.roles[group[0]].decl.name.span
    methods = [item.method for role in group for item in placed[role]]
    planner.add("discover_" + "_".join(group), "discovery", group,
                group_code(ctxs, placed, common, planner.prologue, guard), span, methods,
                _makeup("discovery", placed))
    _first_added(planner)
    _continuations(planner, rest)


def _stored_parts(planner: Planner, roles: list[Context], parts: int, span: Span) -> None:
    """W602 when the commands of split state-dependent discovery, which every module stores (it may
    take any role later), with the discovery program and the behaviours it may start, pass the
    target's program slots."""
    behaviours = {id(m.decl) for ctx in roles for m in ctx.model.roles[ctx.role].methods.values()
                  if m.kind is ast.MethodKind.BEHAVIOR and m.decl.body is not None}
    stored, slots = parts + 1 + len(behaviours), roles[0].target.program_slots
    if stored > slots:
        planner.diagnostics.append(diag.make(
            codes.TOO_MANY_PROGRAMS, span,
            f"the state-dependent discovery is split into {parts} commands, which every module stores; "
            f"with the discovery program and {len(behaviours)} behaviours a module may store {stored} "
            f"programs, and the DCD-VM has {slots} slots (a program that does not find one is a "
            "runtime error): fewer roles or smaller entry code"))


def _first_added(planner: Planner) -> None:
    """After the first fragment: the prologue and the travelling value were in it."""
    planner.prologue = []
    planner.budget += len(planner.trailer)  # only the first fragment carries it
    planner.trailer = b""


Chunk = dict[str, list[EntryItem]]  # role -> its items in one continuation fragment


def _makeup(kind: str, items: dict[str, list[EntryItem]]) -> Makeup:
    return (kind, *((role, *map(id, role_items)) for role, role_items in items.items()))


def _chunk_code(planner: Planner, chunk: Chunk) -> list[Item]:
    return continuation_code([(planner.ctxs[role], items) for role, items in chunk.items()])


def _pack(planner: Planner, rest: dict[str, list[EntryItem]]) -> list[Chunk]:
    """First fit, roles with most code first; a role's items stay in injection order."""
    chunks: list[Chunk] = []
    order = sorted(rest, key=lambda r: -sum(planner.size(i.code) for i in rest[r])) if len(rest) > 1 else rest
    for role in order:
        first = 0
        for item in rest[role]:
            for index in range(first, len(chunks) + 1):
                if index == len(chunks):
                    chunks.append({role: [item]})
                    break
                trial = {**chunks[index], role: chunks[index].get(role, []) + [item]}
                if planner.fits(_chunk_code(planner, trial), _makeup("continuation", trial)):
                    chunks[index] = trial
                    break
            first = index
    return chunks


def _continuations(planner: Planner, rest: dict[str, list[EntryItem]]) -> None:
    for chunk in _pack(planner, {role: items for role, items in rest.items() if items}):
        items = [item for role_items in chunk.values() for item in role_items]
        kinds = {item.kind for item in items}
        kind = kinds.pop() if len(kinds) == 1 else "entry"
        roles = list(chunk)
        span = items[0].span.cover(items[-1].span)
        planner.add(f"{'_'.join(roles)}_{kind}", kind, roles, _chunk_code(planner, chunk), span,
                    [item.method for item in items], _makeup("continuation", chunk),
                    planner.culprit_of(items) if len(items) == 1 else None)


def plan(ctxs: dict[str, Context], deployment: list[str], budget: int,
         prologue: list[Item] | None = None, trailer: bytes = b"", spares: Spares | None = None,
         commands: dict[str, int] | None = None) -> Planner:
    """``commands``: the command numbers of the program's commands (``entry``), for the spare
    numbers of split state-dependent discovery (``watched``)."""
    planner = Planner(ctxs, budget - len(trailer), prologue=list(prologue or []), trailer=trailer,
                      deployment=list(deployment), spares=spares)
    if any(reads_state(ctx) for ctx in ctxs.values()):
        for ctx in ctxs.values():
            ctx.watched = True
        roles = [ctxs[role] for role in deployment]
        items = {role: entry_items(ctxs[role], False) for role in deployment}
        model = roles[0].model
        span = model.roles[deployment[0]].decl.name.span
        methods = [item.method for role in deployment for item in items[role]]
        code = watched_code(roles, items, planner.prologue)
        made = None
        if spares is not None and not planner.fits(code):
            made = split_watched(planner.fits, ctxs, deployment, items, planner.prologue,
                                 watched_numbers(commands or {}))
        if made is None:
            planner.add("discover_" + "_".join(deployment), "discovery", deployment, code, span, methods)
            return planner
        for index, parts in enumerate(made.fragments):  # on every link before the discovery fragment
            first = planner.prologue if index == 0 else []
            part_roles = list(dict.fromkeys(part.role for part in parts))
            planner.add(f"{'_'.join(part_roles)}_entry", "entry", part_roles, install_code(parts, first),
                        parts[0].span.cover(parts[-1].span),
                        [item.method for part in parts for item in part.items],
                        culprit=watched_culprit(parts))
            if index == 0:
                _first_added(planner)
        tested = [ctxs[role] for role in made.roles]
        planner.add("discover_" + "_".join(deployment), "discovery", deployment,
                    watched_code(tested, made.kept, planner.prologue, made.calls, made.tail), span,
                    [item.method for role in made.roles for item in made.kept[role]])
        _stored_parts(planner, roles, sum(len(parts) for parts in made.fragments), span)
        return planner
    groups = form_groups(planner, deployment)
    later: set[str] = set()
    checks: dict[str, bool] = {}
    for group in reversed(groups):
        for role in group:
            checks[role] = bool(later)
        later.update(group)
    splitter = None
    if spares is not None and all(ctx.has("CONTINUE_COMMAND") for ctx in ctxs.values()):
        splitter = HandlerSplitter(planner.fits, planner.size, planner.budget, spares)
    for group in groups:
        items = {}
        for role in group:
            ctxs[role].split_handler = splitter
            try:
                made = split_items(planner, ctxs[role], entry_items(ctxs[role], checks[role]))
            finally:
                ctxs[role].split_handler = None
            # the handlers' commands first: a module has them before it can install a handler
            items[role] = (splitter.pending.pop(role, []) if splitter else []) + made
        plan_group(planner, group, items)
    return planner


def split_items(planner: Planner, ctx: Context, items: list[EntryItem]) -> list[EntryItem]:
    """Startup statements too large for a fragment of their own, split where that is sound;
    commands and behaviours too large, as a chain of commands (``chain``)."""
    result: list[EntryItem] = []
    for item in items:
        alone_fits = planner.fits(continuation_code([(ctx, [item])]))
        if not alone_fits and item.symbol is not None:
            result += _chain(planner, ctx, item)
            continue
        parts = [] if alone_fits else split_statement(item.stmt)
        if not parts:
            result.append(item)
            continue
        smaller = [piece for part in parts for piece in startup_items(part, ctx, item.method)]
        result += split_items(planner, ctx, smaller)
    return result


def _chain(planner: Planner, ctx: Context, item: EntryItem) -> list[EntryItem]:
    if planner.spares is None:
        return [item]
    made = split_method(item, ctx, planner.spares,
                        lambda part: planner.fits(continuation_code([(ctx, [part])])))
    if isinstance(made, Culprit):
        if made.stmt is not None:
            planner.culprits[id(item)] = made.stmt
        return [item]
    items, culprits = made
    planner.culprits.update(culprits)
    return items
