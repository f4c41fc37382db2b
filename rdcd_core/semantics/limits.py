"""Limits of the target (docs/language.md) that the checker reports: role identifiers, command tables
(commands and behaviours). The compiler reports nothing of these twice: its role table has exactly
the identifiers counted here (tests/compiler/test_limits.py compares them).

The role identifiers are counted as the compiler assigns them (docs/vm.md): deployed roles;
roles observed at run time (``connected_role`` and command targets); observed mixins; one per
application of an assumed mixin to a deployed role it can modify.
"""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.model import MethodSymbol
from rdcd_core.syntax import ast
from vm.isa.opcodes import ROLE_IDS, USER_COMMANDS


def check_limits(ctx: Context, deployed: dict[str, ast.Name]) -> None:
    roles = ctx.model.roles
    observed, assumed = ctx.observed_roles, ctx.assumed_mixins
    ids: list[tuple[str, ast.Name]] = list(deployed.items())
    ids += [(r, n) for r, n in observed.items() if not roles[r].is_mixin and r not in deployed]
    ids += [(r, n) for r, n in observed.items() if roles[r].is_mixin]
    applications: list[tuple[str, str]] = []
    for mixin, name in assumed.items():
        if not roles[mixin].is_mixin:
            continue
        for role in deployed:
            if roles[mixin].modifies in ctx.ancestors(role):
                ids.append((f"{mixin}@{role}", name))
                applications.append((mixin, role))
    if len(ids) > ROLE_IDS:
        what, name = ids[ROLE_IDS]
        ctx.report(codes.TOO_MANY_ROLE_IDS, name.span,
                   f"the program needs {len(ids)} role identifiers (deployed and observed roles, "
                   f"one per mixin application); the target has {ROLE_IDS}: the {ROLE_IDS + 1}th is "
                   f"'{what}'; deploy fewer roles or assume fewer mixins")
    for role in deployed:
        _check_table(ctx, role, list(roles[role].methods.values()))
    for mixin, role in applications:
        merged = dict(roles[role].methods)
        merged.update((name, m) for name, m in roles[mixin].methods.items()
                      if m.kind is ast.MethodKind.COMMAND)  # a mixin's behaviours are not compiled (W603)
        _check_table(ctx, mixin, list(merged.values()), applied_to=role)


_TABLE = (ast.MethodKind.COMMAND, ast.MethodKind.BEHAVIOR)  # behaviours run as user commands too


def _check_table(ctx: Context, role: str, methods: list[MethodSymbol], applied_to: str = "") -> None:
    """The role's command table holds its commands and its behaviours (inherited ones included).

    This counts them; the compiler (E603) reports what only the numbering shows: a command keeps
    one number in every role that has it, which can leave no free number within a table.
    """
    entries = [m for m in methods if m.kind in _TABLE and m.decl.body is not None]
    decl = ctx.model.roles[role].decl
    if len(entries) <= USER_COMMANDS or decl is None:
        return
    what = f"'{role}' applied to '{applied_to}'" if applied_to else f"role '{role}'"
    behaviours = sum(1 for m in entries if m.kind is ast.MethodKind.BEHAVIOR)
    counted = f"{len(entries)} commands and behaviours" if behaviours else f"{len(entries)} commands"
    ctx.report(codes.TOO_MANY_COMMANDS, decl.name.span,
               f"{what} has {counted} (inherited ones included); the target's command table holds "
               f"{USER_COMMANDS}, behaviours included: merge or remove some",
               related=tuple(diag.Related(m.decl.name.span, f"{m.kind.value} '{m.name}'")
                             for m in entries))
