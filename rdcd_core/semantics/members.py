"""Members of roles and their copy-down (docs/language.md): duplicates, overriding, abstract members."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.module_api import SELF_PRIMITIVES
from rdcd_core.semantics import codes, states
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.model import (
    ROOT_ROLE,
    ConstantSymbol,
    InvariantSymbol,
    MethodSymbol,
    RoleKind,
    RoleSymbol,
    StateSymbol,
)
from rdcd_core.source import Span
from rdcd_core.syntax import ast


def topological_roles(ctx: Context) -> list[RoleSymbol]:
    """Every role, super-roles before their sub-roles (mixins last)."""
    roles = ctx.model.roles
    plain = [s for s in roles.values() if not s.is_mixin]
    plain.sort(key=lambda s: len(ctx.ancestors(s.name)))
    return plain + [s for s in roles.values() if s.is_mixin]


def copy_down(ctx: Context) -> None:
    for symbol in topological_roles(ctx):
        if symbol.decl is None:
            continue
        own_constants, own_methods, own_invariants, own_states = _own_members(ctx, symbol)
        parent = ctx.model.roles.get(symbol.parent) if symbol.parent else None
        if parent is not None:
            symbol.states.update(parent.states)
            for name, inherited in parent.constants.items():
                symbol.constants[name] = ConstantSymbol(
                    name, inherited.owner, inherited.declaration, inherited.definition, None)
            symbol.methods.update(parent.methods)
            symbol.invariants.extend(parent.invariants)
        base = ctx.model.roles.get(symbol.modifies or "") if symbol.is_mixin else None
        for name, method in own_methods.items():
            shadowed = base.methods.get(name) if base is not None else symbol.methods.get(name)
            _check_override(ctx, shadowed, method)
            symbol.methods[name] = method
        symbol.constants.update(own_constants)
        symbol.invariants.extend(own_invariants)
        symbol.states.update(own_states)


def check_missing_definitions(ctx: Context) -> None:
    for symbol in ctx.model.roles.values():
        _check_missing(ctx, symbol)


def _own_members(ctx: Context, symbol: RoleSymbol) -> tuple[
        dict[str, ConstantSymbol], dict[str, MethodSymbol], list[InvariantSymbol], dict[str, StateSymbol]]:
    decl = symbol.decl
    assert decl is not None
    constants: dict[str, ConstantSymbol] = {}
    methods: dict[str, MethodSymbol] = {}
    invariants: list[InvariantSymbol] = []
    own_states: dict[str, StateSymbol] = {}
    for member in decl.members:
        if isinstance(member, ast.AssignStmt):
            ctx.report(codes.ASSIGN_OUTSIDE_METHOD, member.span,
                       f"'{member.name.text} := …' is an assignment, which only a method can make; "
                       "invariants read state, they never change it: move it into a startup, behavior "
                       "or command method")
            continue
        if isinstance(member, ast.StateDecl):
            if symbol.is_mixin:
                ctx.report(codes.MIXIN_STATE, member.name.span,
                           f"mixin '{symbol.name}' cannot declare state: inside assumeRole the module "
                           f"keeps its base role's state; declare it in '{symbol.modifies}'")
            elif _unique(ctx, symbol, constants, member.name, "constant", own_states):
                own_states[member.name.text] = states.role_state(ctx, symbol.name, member)
            continue
        if isinstance(member, ast.AbstractConstants):
            for name in member.names:
                if _unique(ctx, symbol, constants, name, "constant", own_states):
                    constants[name.text] = ConstantSymbol(name.text, symbol.name, name, None, None)
                    ctx.reference(name, "constant", f"{symbol.name}.{name.text}", True)
        elif isinstance(member, ast.ConstantDef):
            if _unique(ctx, symbol, constants, member.name, "constant", own_states):
                constants[member.name.text] = ConstantSymbol(
                    member.name.text, symbol.name, member.name, member, None)
                ctx.reference(member.name, "constant", f"{symbol.name}.{member.name.text}", True)
        elif isinstance(member, ast.MethodDecl):
            _check_method_decl(ctx, member)
            if _unique(ctx, symbol, methods, member.name, "method"):
                methods[member.name.text] = MethodSymbol(member.name.text, symbol.name, member,
                                                         member.kind)
                kind = "command" if member.kind is ast.MethodKind.COMMAND else "method"
                ctx.reference(member.name, kind, f"{symbol.name}.{member.name.text}", True)
        elif isinstance(member, ast.Invariant):
            if symbol.is_mixin:
                ctx.report(codes.MIXIN_INVARIANT, member.span,
                           f"mixin '{symbol.name}' cannot have invariants; remove this one or make "
                           "the role a sub-role with 'extends'",
                           fixes=(diag.Fix("remove the invariant",
                                           (diag.TextEdit(member.span, ""),)),))
            else:
                invariants.append(InvariantSymbol(symbol.name, member))
    return constants, methods, invariants, own_states


def _unique(ctx: Context, symbol: RoleSymbol, table: dict, name: ast.Name, what: str,
            other: dict | None = None) -> bool:
    if not name.text:
        return False
    if what == "method" and name.text in SELF_PRIMITIVES:
        ctx.report(codes.DUPLICATE_MEMBER, name.span,
                   f"'{name.text}' is a primitive of Module; give the method another name")
        return False
    first = table.get(name.text)
    if first is None and other is not None:
        first = other.get(name.text)  # constants and role state share one namespace
    if first is None:
        return True
    first_span = first.declaration.span if isinstance(first, ConstantSymbol) else first.decl.name.span
    ctx.report(codes.DUPLICATE_MEMBER, name.span,
               f"{what} '{name.text}' is already declared in role '{symbol.name}'; "
               "rename or remove one",
               related=(diag.Related(first_span, f"first declaration of '{name.text}'"),))
    return False


def _check_method_decl(ctx: Context, method: ast.MethodDecl) -> None:
    kinds = [m for m in method.modifiers if m.keyword != "abstract"]
    abstracts = [m for m in method.modifiers if m.keyword == "abstract"]
    for extra in kinds[1:] + abstracts[1:]:
        ctx.report(codes.BAD_MODIFIERS, extra.span,
                   f"method '{method.name.text}' has more than one kind; keep one of "
                   "startup, behavior or command",
                   fixes=(diag.Fix(f"remove '{extra.keyword}'",
                                   (diag.TextEdit(Span(extra.span.start, extra.span.end + 1), ""),)),))
    if abstracts and method.body is not None:
        ctx.report(codes.ABSTRACT_WITH_BODY, abstracts[0].span,
                   f"abstract method '{method.name.text}' cannot have a body; remove 'abstract' "
                   "or the body")


def _check_override(ctx: Context, inherited: MethodSymbol | None, method: MethodSymbol) -> None:
    if inherited is None or inherited.kind is method.kind:
        return
    ctx.report(codes.OVERRIDE_KIND, method.decl.name.span,
               f"'{method.name}' is a {inherited.kind.value} method in '{inherited.owner}'; an "
               f"override must keep that kind, not make it {method.kind.value}",
               related=(diag.Related(inherited.decl.name.span, "the overridden method"),))


_SAMPLE = {"int": "0", "axis": "EAST_WEST", "dir": "EAST", "event": "EVENT_PROXIMITY_0"}


def _check_missing(ctx: Context, symbol: RoleSymbol) -> None:
    if symbol.kind is RoleKind.ABSTRACT or symbol.decl is None:
        return
    missing_constants = [c for c in symbol.constants.values() if c.definition is None]
    missing_methods = [m for m in symbol.methods.values() if m.is_abstract]
    if not missing_constants and not missing_methods:
        return
    decl = symbol.decl
    names = [f"constant '{c.name}'" for c in missing_constants]
    names += [f"method '{m.name}'" for m in missing_methods]
    related = [diag.Related(c.declaration.span, f"abstract constant '{c.name}' of '{c.owner}'")
               for c in missing_constants]
    related += [diag.Related(m.decl.name.span, f"abstract method '{m.name}' of '{m.owner}'")
                for m in missing_methods]
    fixes = []
    if not symbol.is_mixin:
        fixes.append(diag.Fix(f"declare '{symbol.name}' abstract",
                              (diag.TextEdit(Span(decl.span.start, decl.span.start), "abstract "),)))
    # Definitions can only be added for members inherited abstract: one this role declares
    # abstract itself would then be declared twice.
    inherited_constants = [c for c in missing_constants if c.owner != symbol.name]
    inherited_methods = [m for m in missing_methods if m.owner != symbol.name]
    lines = "".join(f"  constant {c.name} := {_SAMPLE.get(str(c.type), '0')};\n"
                    for c in inherited_constants)
    lines += "".join(f"  {_kind_prefix(m)}{m.name}() {{ }}\n" for m in inherited_methods)
    closing = max(decl.span.start, decl.span.end - 1)
    title = "add the missing constant definitions" if not inherited_methods else \
        "add the missing definitions"
    if lines:
        fixes.append(diag.Fix(title, (diag.TextEdit(Span(closing, closing), lines),)))
    what = "mixin" if symbol.is_mixin else "role"
    them = "them" if len(names) > 1 else "it"
    todo = f"define {them} (a mixin cannot be abstract)" if symbol.is_mixin else \
        f"define {them} or declare the role abstract"
    ctx.report(codes.MISSING_DEFINITIONS, decl.name.span,
               f"{what} '{symbol.name}' does not define {_listed(names)}; {todo}",
               related=related, fixes=fixes)


def _listed(names: list[str], limit: int = 10) -> str:
    """The names, the first ``limit`` of a long list only: a message stays one readable line."""
    if len(names) <= limit:
        return ", ".join(names)
    return f"{', '.join(names[:limit])} and {len(names) - limit} more"


def _kind_prefix(method: MethodSymbol) -> str:
    return "" if method.kind is ast.MethodKind.PLAIN else f"{method.kind.value} "


def concrete_owners(ctx: Context, role: str, children: dict[str, list[str]]) -> list[str]:
    """Concrete non-mixin roles that are ``role`` or descend from it (children map given)."""
    result: list[str] = []
    stack = [role]
    seen: set[str] = set()
    while stack:
        current = stack.pop()
        if current in seen:
            continue
        seen.add(current)
        if ctx.model.roles[current].kind is RoleKind.CONCRETE:
            result.append(current)
        stack.extend(children.get(current, ()))
    return result


def children_map(ctx: Context) -> dict[str, list[str]]:
    children: dict[str, list[str]] = {}
    for symbol in ctx.model.roles.values():
        if symbol.parent is not None and symbol.name != ROOT_ROLE:
            children.setdefault(symbol.parent, []).append(symbol.name)
    return children
