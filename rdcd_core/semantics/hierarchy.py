"""Role symbols and the role hierarchy (docs/language.md): duplicates, super-roles, cycles, mixins."""

from __future__ import annotations

from collections.abc import Callable

from rdcd_core import diagnostics as diag
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context, did_you_mean
from rdcd_core.semantics.model import ROOT_ROLE, RoleKind, RoleSymbol
from rdcd_core.syntax import ast


def build_roles(ctx: Context, program: ast.Program) -> None:
    roles = ctx.model.roles
    roles[ROOT_ROLE] = RoleSymbol(ROOT_ROLE, RoleKind.ABSTRACT, None, None, None)
    for decl in program.roles:
        _declare(ctx, decl)
    for symbol in list(roles.values()):
        if symbol.decl is not None:
            _resolve_links(ctx, symbol)
    _break_cycles(ctx)


def _declare(ctx: Context, decl: ast.RoleDecl) -> None:
    name = decl.name.text
    if not name:
        return
    roles = ctx.model.roles
    if name == ROOT_ROLE:
        ctx.report(codes.REDEFINES_MODULE, decl.name.span,
                   "'Module' is the predefined root role; give this role another name")
        return
    first = roles.get(name)
    if first is not None and first.decl is not None:
        ctx.report(codes.DUPLICATE_ROLE, decl.name.span,
                   f"role '{name}' is already declared; rename or remove this one",
                   related=(diag.Related(first.decl.name.span, f"first declaration of '{name}'"),))
        return
    if decl.modifies is not None:
        kind = RoleKind.MIXIN
        if decl.is_abstract:
            span = decl.abstract_span or decl.name.span
            fix = diag.Fix("remove 'abstract'", (diag.TextEdit(_with_space(span), ""),))
            ctx.report(codes.ABSTRACT_MIXIN, span,
                       f"mixin '{name}' cannot be abstract; remove 'abstract'", fixes=(fix,))
    else:
        kind = RoleKind.ABSTRACT if decl.is_abstract else RoleKind.CONCRETE
    roles[name] = RoleSymbol(name, kind, decl, ROOT_ROLE if kind is not RoleKind.MIXIN else None, None)
    ctx.reference(decl.name, "role", name, is_definition=True)


def _with_space(span: ast.Span) -> ast.Span:
    return ast.Span(span.start, span.end + 1)


def _resolve_links(ctx: Context, symbol: RoleSymbol) -> None:
    decl = symbol.decl
    assert decl is not None
    if decl.extends is not None and decl.extends.text:
        parent = _link(
            ctx, decl.extends, codes.UNKNOWN_SUPER, f"unknown super-role '{decl.extends.text}'",
            codes.EXTENDS_MIXIN,
            lambda mixin: f"'{decl.name.text}' cannot extend mixin '{mixin.name}'; extend the role "
                          f"it modifies ('{mixin.modifies or ROOT_ROLE}') instead")
        if parent is not None:
            symbol.parent = parent
    if decl.modifies is not None and decl.modifies.text:
        symbol.modifies = _link(
            ctx, decl.modifies, codes.UNKNOWN_MODIFIED,
            f"mixin '{decl.name.text}' modifies unknown role '{decl.modifies.text}'",
            codes.MODIFIES_MIXIN,
            lambda mixin: f"mixin '{decl.name.text}' cannot modify mixin '{mixin.name}'; "
                          "modify a non-mixin role")


def _link(ctx: Context, target: ast.Name, unknown_code: str, unknown: str, mixin_code: str,
          on_mixin: Callable[[RoleSymbol], str]) -> str | None:
    """The non-mixin role ``target`` names; else reports it (unknown, or a mixin) and gives None."""
    roles = ctx.model.roles
    found = roles.get(target.text)
    if found is None:
        candidates = [r for r, s in roles.items() if not s.is_mixin]
        suffix, fixes = did_you_mean(target.text, candidates, target.span)
        ctx.report(unknown_code, target.span, unknown + suffix, fixes=fixes)
        return None
    ctx.reference(target, "role", found.name)
    if found.is_mixin:
        ctx.report(mixin_code, target.span, on_mixin(found), related=_decl_related(found, "the mixin"))
        return None
    return found.name


def _decl_related(symbol: RoleSymbol, what: str) -> tuple[diag.Related, ...]:
    if symbol.decl is None:
        return ()
    return (diag.Related(symbol.decl.name.span, f"{what} '{symbol.name}' is declared here"),)


def _break_cycles(ctx: Context) -> None:
    """Reports each inheritance cycle once and cuts it (its roles then extend Module)."""
    roles = ctx.model.roles
    done: set[str] = set()
    for start in roles:
        path: list[str] = []
        on_path: set[str] = set()
        current: str | None = start
        while current is not None and current not in done and current not in on_path:
            path.append(current)
            on_path.add(current)
            current = roles[current].parent
        if current is not None and current in on_path:
            cycle = path[path.index(current):]
            names = " -> ".join([*cycle, cycle[0]])
            for name in cycle:
                decl = roles[name].decl
                if decl is not None and decl.extends is not None:
                    ctx.report(codes.INHERITANCE_CYCLE, decl.extends.span,
                               f"inheritance cycle {names}; remove one 'extends'")
                roles[name].parent = ROOT_ROLE
        done.update(path)
