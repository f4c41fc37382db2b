"""Checks invariants and method bodies in the scope of every concrete role that owns them."""

from __future__ import annotations

from rdcd_core.semantics import expressions, scoping
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.env import Env
from rdcd_core.semantics.members import concrete_owners
from rdcd_core.semantics.model import ROOT_ROLE, RoleSymbol
from rdcd_core.syntax import ast


def check_bodies(ctx: Context, children: dict[str, list[str]]) -> None:
    roles = ctx.model.roles
    for symbol in list(roles.values()):
        if symbol.decl is None:
            continue
        if symbol.is_mixin:
            base = symbol.modifies or ROOT_ROLE
            owners = [roles[r] for r in concrete_owners(ctx, base, children)] or [roles[base]]
            mixins = (symbol,)
        else:
            owners = [roles[r] for r in concrete_owners(ctx, symbol.name, children)] or [symbol]
            mixins = ()
        for member in symbol.decl.members:
            if isinstance(member, ast.Invariant) and not symbol.is_mixin:
                for owner in owners:
                    expressions.check_bool(Env(ctx, owner, symbol), member.expr, "an invariant")
            elif isinstance(member, ast.MethodDecl) and member.body is not None:
                for owner in _method_owners(symbol, owners, member):
                    env = Env(ctx, owner, symbol, mixins=mixins, method=member)
                    scoping.check_block(env, member.body)


def _method_owners(symbol: RoleSymbol, owners: list[RoleSymbol],
                   method: ast.MethodDecl) -> list[RoleSymbol]:
    if symbol.is_mixin:
        return owners
    found = [o for o in owners if (m := o.methods.get(method.name.text)) and m.decl is method]
    return found or [symbol]
