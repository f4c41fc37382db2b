"""Constant definitions: folding, allowed types, agreement of types across the hierarchy (§5.2)."""

from __future__ import annotations

from dataclasses import replace

from rdcd_core import diagnostics as diag
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.env import Env
from rdcd_core.semantics.expressions import a_type, constant_value
from rdcd_core.semantics.model import ROOT_ROLE, RoleSymbol
from rdcd_core.syntax import ast
from rdcd_core.types import Type

_ALLOWED = {Type.INT, Type.AXIS, Type.DIR, Type.EVENT}


def scope_of(ctx: Context, symbol: RoleSymbol) -> Env:
    """The scope of a role's own code: a mixin is seen applied to the role it modifies."""
    if symbol.is_mixin:
        base = ctx.model.roles.get(symbol.modifies or ROOT_ROLE) or ctx.model.roles[ROOT_ROLE]
        return Env(ctx, base, symbol, mixins=(symbol,))
    return Env(ctx, symbol, symbol)


def fold_constants(ctx: Context) -> None:
    checked: set[int] = set()
    for symbol in ctx.model.roles.values():
        env = scope_of(ctx, symbol)
        for constant in symbol.constants.values():
            if constant.definition is None:
                continue
            holder = replace(env, constant=constant.name)
            type_, _ = constant_value(holder, constant, None)
            definition = constant.definition
            if type_ is not None and type_ not in _ALLOWED and id(definition) not in checked:
                checked.add(id(definition))
                ctx.report(codes.CONSTANT_TYPE, definition.value.span,
                           f"constant '{constant.name}' is a {type_.value}; a constant must be an "
                           "int, axis, dir or event")
    _family_types(ctx)


def _family_root(ctx: Context, symbol: RoleSymbol, name: str) -> str:
    if symbol.is_mixin:
        base = ctx.model.roles.get(symbol.modifies or "")
        return _family_root(ctx, base, name) if base and name in base.constants else symbol.name
    for ancestor in reversed(ctx.ancestors(symbol.name)):
        if name in ctx.model.roles[ancestor].constants:
            return ancestor
    return symbol.name


def _family_types(ctx: Context) -> None:
    families: dict[tuple[str, str], dict[int, tuple[ast.ConstantDef, Type | None, str]]] = {}
    members: dict[tuple[str, str], list] = {}
    for symbol in ctx.model.roles.values():
        for constant in symbol.constants.values():
            key = (_family_root(ctx, symbol, constant.name), constant.name)
            members.setdefault(key, []).append(constant)
            if constant.definition is not None:
                entry = (constant.definition, constant.type, constant.owner)
                families.setdefault(key, {}).setdefault(id(constant.definition), entry)
    for key, definitions in families.items():
        ordered = sorted(definitions.values(), key=lambda entry: entry[0].span.start)
        typed = [entry for entry in ordered if entry[1] is not None]
        if not typed:
            continue
        first_def, first_type, first_owner = typed[0]
        for definition, type_, _owner in typed[1:]:
            if type_ is not first_type:
                ctx.report(codes.CONSTANT_TYPE_DISAGREES, definition.value.span,
                           f"constant '{key[1]}' is {a_type(type_)} here but {a_type(first_type)} in "
                           f"'{first_owner}'; every definition of '{key[1]}' must have one type",
                           related=(diag.Related(first_def.value.span,
                                                 f"'{key[1]}' is {a_type(first_type)} here"),))
        for constant in members.get(key, ()):
            if constant.definition is None:
                constant.type = first_type
