"""The deployment (docs/language.md): valid entries, discovery order, dead roles."""

from __future__ import annotations

import heapq

from rdcd_core import diagnostics as diag
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context, did_you_mean
from rdcd_core.semantics.model import ROOT_ROLE, RoleKind
from rdcd_core.semantics.walk import expr_nodes
from rdcd_core.source import Span
from rdcd_core.syntax import ast


def check_deployment(ctx: Context) -> dict[str, ast.Name]:
    """Fills ``model.deployment``; returns the deployed names' occurrences."""
    program = ctx.model.program
    roles = ctx.model.roles
    deployment = program.deployment
    if deployment is None:  # the parser reports the missing deployment
        return {}
    seen: dict[str, ast.Name] = {}
    names = deployment.roles
    for index, name in enumerate(names):
        symbol = roles.get(name.text)
        if symbol is None:
            candidates = [r for r, s in roles.items() if s.kind is RoleKind.CONCRETE]
            suffix, fixes = did_you_mean(name.text, candidates, name.span)
            ctx.report(codes.UNKNOWN_DEPLOYED, name.span,
                       f"unknown role '{name.text}' in the deployment{suffix}", fixes=fixes)
            continue
        ctx.reference(name, "role", symbol.name)
        removal = _removal(names, index)
        if symbol.kind is RoleKind.ABSTRACT:
            subs = [r for r in ctx.model.concrete_subroles(symbol.name)] if symbol.name != ROOT_ROLE \
                else []
            hint = f"deploy its concrete sub-roles ({', '.join(subs)})" if subs else \
                "deploy a concrete sub-role"
            ctx.report(codes.ABSTRACT_DEPLOYED, name.span,
                       f"'{symbol.name}' is abstract and cannot be deployed; {hint}",
                       fixes=(diag.Fix(f"remove '{symbol.name}'", (removal,)),))
        elif symbol.kind is RoleKind.MIXIN:
            ctx.report(codes.MIXIN_DEPLOYED, name.span,
                       f"'{symbol.name}' is a mixin and cannot be deployed; modules take it only "
                       "through self.assumeRole",
                       fixes=(diag.Fix(f"remove '{symbol.name}'", (removal,)),))
        elif symbol.name in seen:
            ctx.report(codes.REPEATED_DEPLOYED, name.span,
                       f"'{symbol.name}' is already deployed; remove the repetition",
                       related=(diag.Related(seen[symbol.name].span, "first deployed here"),),
                       fixes=(diag.Fix(f"remove the second '{symbol.name}'", (removal,)),))
        else:
            seen[symbol.name] = name
            ctx.model.deployment.append(symbol.name)
    return seen


def _removal(names: tuple[ast.Name, ...], index: int) -> diag.TextEdit:
    """Deletes entry ``index`` of the deployment with one adjacent comma."""
    if index > 0:
        return diag.TextEdit(Span(names[index - 1].span.end, names[index].span.end), "")
    if len(names) > 1:
        return diag.TextEdit(Span(names[0].span.start, names[1].span.start), "")
    return diag.TextEdit(names[0].span, "")


def observed_roles(ctx: Context, role: str) -> list[tuple[str, ast.Name]]:
    """Roles named by connected_role in the invariants of ``role`` (inherited ones included)."""
    found: list[tuple[str, ast.Name]] = []
    for invariant in ctx.model.roles[role].invariants:
        found.extend(_observed_in(ctx, invariant.decl))
    return found


def _observed_in(ctx: Context, invariant: ast.Invariant) -> list[tuple[str, ast.Name]]:
    cached = ctx.observed.get(id(invariant))
    if cached is None:
        cached = []
        for node in expr_nodes(invariant.expr):
            if isinstance(node, ast.FunctionCall) and node.name.text == "connected_role" \
                    and len(node.args) == 2:
                arg = ast.unparen(node.args[1]) if not isinstance(node.args[1], ast.Block) else None
                if isinstance(arg, ast.NameRef) and arg.name.text in ctx.model.roles:
                    cached.append((arg.name.text, arg.name))
        ctx.observed[id(invariant)] = cached
    return cached


def check_discovery_order(ctx: Context, seen: dict[str, ast.Name]) -> None:
    order = ctx.model.deployment
    position = {name: index for index, name in enumerate(order)}
    depends: dict[str, list[tuple[str, str, ast.Name]]] = {}  # A -> [(B, R, occurrence)]
    deployed_under: dict[str, list[str]] = {}  # R -> deployed roles that are R or sub-roles of R
    for role in order:
        for ancestor in ctx.ancestors(role):
            deployed_under.setdefault(ancestor, []).append(role)
    for role in order:
        for observed, occurrence in observed_roles(ctx, role):
            for other in deployed_under.get(observed, ()):
                if other != role:
                    depends.setdefault(role, []).append((other, observed, occurrence))
    fixed = _reorder(order, depends)
    deployment = ctx.model.program.deployment
    fixes: tuple[diag.Fix, ...] = ()
    if fixed is not None and deployment is not None and deployment.roles:
        span = Span(deployment.roles[0].span.start, deployment.roles[-1].span.end)
        fixes = (diag.Fix("reorder the deployment", (diag.TextEdit(span, ", ".join(fixed)),)),)
    for role, needs in depends.items():
        late = [need for need in needs if position[need[0]] > position[role]]
        cyclic = [need for need in late if fixed is None and _reaches(depends, need[0], role)]
        ordering = [need for need in late if need not in cyclic]
        if cyclic:
            ctx.report(codes.DISCOVERY_CYCLE, seen[role].span,
                       f"'{role}' and {_names([n[0] for n in cyclic])} observe each other with "
                       "connected_role; "
                       "no discovery order lets each see the other: make one independent of "
                       "the other", related=_related(role, cyclic))
        if ordering:
            ctx.report(codes.DISCOVERY_ORDER, seen[role].span,
                       f"'{role}' observes {_names([n[1] for n in ordering])} with "
                       f"connected_role but is discovered before {_names([n[0] for n in ordering])}"
                       f"; deploy {'it' if len(ordering) == 1 else 'them'} before '{role}'",
                       related=_related(role, ordering), fixes=fixes)


def _names(names: list[str]) -> str:
    parts = [f"'{name}'" for name in dict.fromkeys(names)]
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


def _related(role: str, needs: list[tuple[str, str, ast.Name]]) -> tuple[diag.Related, ...]:
    spans = {}
    for _, observed, occurrence in needs:
        spans.setdefault(occurrence.span, f"'{role}' observes '{observed}' here")
    return tuple(diag.Related(span, message) for span, message in spans.items())


def _reorder(order: list[str], depends: dict[str, list[tuple[str, str, ast.Name]]]) -> list[str] | None:
    """The deployment order closest to ``order`` that respects ``depends``; None on a cycle.

    Each step places the first role of ``order`` whose needs are placed (kept in a heap of
    positions, so that long deployments stay fast)."""
    position = {role: index for index, role in enumerate(order)}
    waiting: dict[str, int] = {}  # role -> how many of its needs are not placed yet
    needed_by: dict[str, list[str]] = {}
    for role in order:
        needs = {other for other, _, _ in depends.get(role, ())}
        waiting[role] = len(needs)
        for other in needs:
            needed_by.setdefault(other, []).append(role)
    ready = [position[role] for role in order if not waiting[role]]  # ascending: already a heap
    result: list[str] = []
    while ready:
        role = order[heapq.heappop(ready)]
        result.append(role)
        for other in needed_by.get(role, ()):
            waiting[other] -= 1
            if not waiting[other]:
                heapq.heappush(ready, position[other])
    return result if len(result) == len(order) else None


def _reaches(depends: dict[str, list[tuple[str, str, ast.Name]]], start: str, goal: str) -> bool:
    stack, seen = [start], {start}
    while stack:
        current = stack.pop()
        if current == goal:
            return True
        for other, _, _ in depends.get(current, ()):
            if other not in seen:
                seen.add(other)
                stack.append(other)
    return False


def check_dead_roles(ctx: Context) -> None:
    roles = ctx.model.roles
    used: set[str] = set()
    for deployed in ctx.model.deployment:
        used.update(ctx.ancestors(deployed))
    for reference in ctx.model.references:
        if reference.kind == "role" and not reference.is_definition:
            used.add(reference.target)
    deployment = ctx.model.program.deployment
    for name, symbol in roles.items():
        if symbol.kind is not RoleKind.CONCRETE or name in used or symbol.decl is None:
            continue
        fixes = ()
        if deployment is not None:
            where = deployment.roles[-1].span.end if deployment.roles else deployment.span.end - 1
            text = f", {name}" if deployment.roles else f"{name} "
            fixes = (diag.Fix(f"deploy '{name}'", (diag.TextEdit(Span(where, where), text),)),)
        ctx.report(codes.DEAD_ROLE, symbol.decl.name.span,
                   f"role '{name}' is never deployed, extended or referenced; deploy it or "
                   "remove it", fixes=fixes)
