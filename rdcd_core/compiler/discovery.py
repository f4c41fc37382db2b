"""Discovery code: test a role's invariants, take the role (SET_ROLE_NOTIFY), run its entry items.

Sibling roles that share leading invariants are discovered by one fragment: the shared tests run
once, then each role's own tests. Tests are simplified by exhaustive evaluation over the local
state space (axis x connected set, 768 states): a test that always holds on the states that reach
it is dropped, and a cheaper test that agrees with it on those states replaces it.

Arrival order: a fragment whose tests read neighbour roles, and a continuation fragment (which
tests the role its discovery fragment gave), starts with SLEEP: on every module it waits one
second before testing, so that the roles announced by fragments injected just before it (also
when a lost packet was retransmitted) have arrived. The injection plan keeps deployment order.
"""

from __future__ import annotations

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.entry import EntryItem
from rdcd_core.compiler.exprgen import cjump, emit
from rdcd_core.compiler.fold import fold, local_shape, type_of, vector_of
from rdcd_core.compiler.geometry import ALL_STATES, LOCAL_STATES
from rdcd_core.compiler.ir import Body, Ins, Item, Label, code_size
from rdcd_core.compiler.priority import Guard
from rdcd_core.syntax import ast
from rdcd_core.types import Type


def state_mask(expr: ast.Node, ctx: Context) -> int | None:
    """Bit i set when ``expr`` holds in local state i; None if it is not a local expression."""
    shape = local_shape(expr, ctx)
    if shape is None:
        return None
    key = ("mask", shape)  # a large role's invariants repeat a few shapes
    if key not in ctx.cache:
        values = vector_of(shape, ctx, LOCAL_STATES)
        ctx.cache[key] = int("".join("1" if value else "0" for value in reversed(values)), 2)
    return ctx.cache[key]  # type: ignore[return-value]


def candidates(expr: ast.Node, ctx: Context) -> list[ast.Node]:
    """Cheaper tests that may agree with ``expr`` on some states: zero tests of its parts."""
    key = ("candidates", id(expr))
    if key not in ctx.cache:
        found: list[ast.Node] = [expr]
        for node in ast.walk(expr):
            if not isinstance(node, (ast.SelfCall, ast.FunctionCall)) or fold(node, ctx) is not None:
                continue
            if type_of(node, ctx) not in (Type.INT, Type.CONNSET):
                continue
            zero = ast.IntLit(0, node.span)
            for op in ("!=", "=="):
                found.append(ast.Binary(op, node, zero, node.span, node.span))
        ctx.cache[key] = found
    return ctx.cache[key]


def emit_test(expr: ast.Node, ctx: Context, fail: Label, paths: int, out: list[Item]) -> int:
    """Code that jumps to ``fail`` unless ``expr`` holds; returns the states that pass. A
    conjunction is tested part by part, each part in the states the parts before let through."""
    inner = ast.unparen(expr)
    if isinstance(inner, ast.Binary) and inner.op == "&&":
        paths = emit_test(inner.left, ctx, fail, paths, out)
        return emit_test(inner.right, ctx, fail, paths, out)
    mask = state_mask(expr, ctx)
    saved, ctx.states = ctx.states, paths  # the tests run in the states the earlier ones let through
    try:
        if mask is None:
            cjump(expr, fail, False, ctx, out)
            return paths
        if paths & ~mask == 0:
            return paths
        if paths & mask == 0:
            emit(out, "GOTO", fail, span=expr.span)
            return 0
        out.extend(_cheapest_test(expr, mask, ctx, fail, paths))
        return paths & mask
    finally:
        ctx.states = saved


def _cheapest_test(expr: ast.Node, mask: int, ctx: Context, fail: Label, paths: int) -> list[Item]:
    """The smallest code among the tests that agree with ``expr`` on ``paths`` and that the target
    can run; if none can, ``expr``'s own code with the diagnostics that say why."""
    best: list[Item] | None = None
    refused: list | None = None
    for candidate in candidates(expr, ctx):
        other = state_mask(candidate, ctx)
        if other is None or (other ^ mask) & paths:
            continue
        code: list[Item] = []
        kept, ctx.diagnostics = ctx.diagnostics, []
        cjump(candidate, fail, False, ctx, code)
        problems, ctx.diagnostics = ctx.diagnostics, kept
        if problems:  # the target cannot run this form
            refused = refused if refused is not None else problems
            continue
        if best is None or code_size(code) < code_size(best):
            best = code
    if best is None and refused:
        ctx.diagnostics.extend(refused)
    return best or []


def invariants(ctx: Context) -> list[ast.Node]:
    return [inv.decl.expr for inv in ctx.model.roles[ctx.role].invariants]


def signature(expr: ast.Node, ctx: Context) -> tuple:
    code: list[Item] = []
    kept, ctx.diagnostics = ctx.diagnostics, []  # only compares code: emit_test reports
    cjump(expr, Label(), False, ctx, code)
    problems, ctx.diagnostics = ctx.diagnostics, kept
    if problems:  # code the target cannot run is no code to share
        return (("unexpressed", ctx.role, id(expr)),)
    return tuple((i.op, tuple("L" if isinstance(a, Label) else a for a in i.args))
                 for i in code if isinstance(i, Ins))


def common_prefix(ctxs: list[Context]) -> int:
    lists = [invariants(ctx) for ctx in ctxs]
    paths = [ALL_STATES] * len(ctxs)  # each test's code is made for the states that reach it
    count = 0
    for index in range(min(len(items) for items in lists)):
        decls = {id(ctx.model.roles[ctx.role].invariants[index].decl) for ctx in ctxs}
        sigs = set()
        for position, (items, ctx) in enumerate(zip(lists, ctxs, strict=True)):
            saved, ctx.states = ctx.states, paths[position]
            sigs.add(signature(items[index], ctx))
            ctx.states = saved
            mask = state_mask(items[index], ctx)
            if mask is not None:
                paths[position] &= mask
        if len(decls) != 1 or len(sigs) != 1:
            break
        count += 1
    return count


def role_mask(exprs: list[ast.Node], ctx: Context, *, local_only: bool = False) -> int | None:
    """The states where every expression holds; None if one is not local (``local_only``: the
    states where every local one holds, non-local ones ignored)."""
    mask = ALL_STATES
    for expr in exprs:
        part = state_mask(expr, ctx)
        if part is None:
            if local_only:
                continue
            return None
        mask &= part
    return mask


def group_code(ctxs: list[Context], placed: dict[str, list[EntryItem]], common: int,
               prologue: list[Item] | tuple = (), guard: Guard | None = None) -> list[Item]:
    """``guard`` (``plan.Planner.guard``): whether a role deployed before the group can hold where
    one of its roles holds, and whether the group must wait for such a role's fragment."""
    out: list[Item] = list(prologue)
    migrate = Label("migrate")
    paths = ALL_STATES
    first_span = ctxs[0].model.roles[ctxs[0].role].decl.name.span
    if any(observes_roles(ctx) for ctx in ctxs) or (guard is not None and guard.waits):
        emit(out, "SLEEP", span=first_span)
    if guard is not None and guard.guarded:  # first role wins: a module that took one keeps it
        emit(out, "HAS_ROLE", 0, span=first_span)
        emit(out, "IF_FALSE_GOTO", migrate, span=first_span)
    for expr in invariants(ctxs[0])[:common]:
        paths = emit_test(expr, ctxs[0], migrate, paths, out)
    for ctx in ctxs:
        following = Label("next")
        own = invariants(ctx)[common:]
        role_paths = paths
        for expr in own:
            role_paths = emit_test(expr, ctx, following, role_paths, out)
        span = ctx.model.roles[ctx.role].decl.name.span
        emit(out, "SET_ROLE_NOTIFY", ctx.table.id_of(ctx.role) or 0, span=span)
        for item in placed.get(ctx.role, []):
            out.extend(item.code)
        emit(out, "GOTO", migrate, span=span)
        out.append(following)
        mask = role_mask(own, ctx)
        if mask is not None:
            paths &= ~mask
    out.append(migrate)
    emit(out, "MIGRATE_CONTINUE", span=first_span)
    return out


def reads_state(ctx: Context) -> bool:
    """Whether the role's invariants read a state or the neighbours' values."""
    for inv in ctx.model.roles[ctx.role].invariants:
        for node in ast.walk(inv.decl.expr):
            if isinstance(node, ast.NeighbourValues):
                return True
            if isinstance(node, ast.NameRef) and ctx.state(node.name.text) is not None:
                return True
    return False


def watched_code(ctxs: list[Context], items: dict[str, list[EntryItem]], prologue: list[Item],
                 calls: dict[str, int] | None = None, tail: int = 0) -> list[Item]:
    """Discovery when invariants read state: a program of its own on every module (RUN_LOCAL),
    run again whenever a value of the module changes (END_WAIT); it takes the first deployed role
    whose invariants hold, and runs that role's entry items when it takes it.

    Split (``watched``): ``calls[role]`` is the command that runs the rest of the role's entry
    items after those given here; ``tail`` the command that tests the roles deployed after
    ``ctxs`` (``recheck_code``)."""
    first = ctxs[0]
    span = first.model.roles[first.role].decl.name.span
    recheck = recheck_code(ctxs, items, [ctx.role for ctx in ctxs], calls, tail)
    out: list[Item] = list(prologue)
    first.need("RUN_LOCAL", span, "roles that depend on state need the extension instruction")
    emit(out, "RUN_LOCAL", Body(recheck), span=span)
    emit(out, "MIGRATE_CONTINUE", span=span)
    return out


def recheck_code(ctxs: list[Context], items: dict[str, list[EntryItem]], deployed: list[str],
                 calls: dict[str, int] | None = None, tail: int = 0) -> list[Item]:
    """The tests of the roles of ``ctxs`` in their order, taking the first that holds (``deployed``:
    every deployed role). When none holds: the module has no role, or (``tail``) the run goes on
    in command ``tail``, which tests the roles deployed after them (``CONTINUE_COMMAND``)."""
    first = ctxs[0]
    span = first.model.roles[first.role].decl.name.span
    recheck: list[Item] = []
    done = Label("done")
    always = False
    for ctx in ctxs:
        following = Label("next")
        paths = ALL_STATES
        exprs = invariants(ctx)
        for expr in exprs:
            paths = emit_test(expr, ctx, following, paths, recheck)
        role_span = ctx.model.roles[ctx.role].decl.name.span
        role_id = ctx.table.id_of(ctx.role) or 0
        if not any(o != ctx.role and ctx.model.is_subrole(o, ctx.role) for o in deployed):
            emit(recheck, "HAS_ROLE", role_id, span=role_span)  # kept: nothing to do
            emit(recheck, "IF_TRUE_GOTO", done, span=role_span)
        emit(recheck, "SET_ROLE_NOTIFY", role_id, span=role_span)
        for item in items.get(ctx.role, []):
            recheck.extend(item.code)
        if calls and ctx.role in calls:  # the rest of the entry, in this run
            emit(recheck, "CONTINUE_COMMAND", calls[ctx.role], span=role_span)
        else:
            emit(recheck, "GOTO", done, span=role_span)
        recheck.append(following)
        if not exprs:
            always = True
            break
    if not always and tail:  # none of these holds: the roles after them, in this run
        emit(recheck, "CONTINUE_COMMAND", tail, span=span)
    elif not always:  # no role holds: the module has none
        emit(recheck, "SET_ROLE_NOTIFY", 0, span=span)
    recheck.append(done)
    emit(recheck, "END_WAIT", span=span)
    return recheck


def observes_roles(ctx: Context) -> bool:
    """Whether the role's invariants read neighbour roles announced by earlier fragments."""
    return any(isinstance(node, ast.FunctionCall) and node.name.text == "connected_role"
               for inv in ctx.model.roles[ctx.role].invariants for node in ast.walk(inv.decl.expr))


def continuation_code(parts: list[tuple[Context, list[EntryItem]]]) -> list[Item]:
    """Entry items that did not fit their discovery fragment, for one or more roles: each part
    runs where its role is held (a module holds one role, so at most one part runs)."""
    out: list[Item] = []
    migrate = Label("migrate")
    emit(out, "SLEEP", span=parts[0][1][0].span)
    for ctx, items in parts:
        following = Label("next")
        span = items[0].span
        emit(out, "HAS_ROLE", ctx.table.id_of(ctx.role) or 0, span=span)
        emit(out, "IF_FALSE_GOTO", following, span=span)
        for item in items:
            out.extend(item.code)
        emit(out, "GOTO", migrate, span=span)
        out.append(following)
    out.append(migrate)
    emit(out, "MIGRATE_CONTINUE", span=parts[0][1][0].span)
    return out
