"""Statements, blocks and the scoping of assumeRole and handleEvent (docs/language.md)."""

from __future__ import annotations

from dataclasses import replace

from rdcd_core import diagnostics as diag
from rdcd_core.module_api import ACTIONS
from rdcd_core.semantics import calls, codes, expressions, states
from rdcd_core.semantics.context import did_you_mean
from rdcd_core.semantics.env import Env
from rdcd_core.semantics.model import ROOT_ROLE, RoleSymbol, Value
from rdcd_core.syntax import ast
from rdcd_core.types import Type


def check_block(env: Env, block: ast.Block) -> None:
    for statement in block.statements:
        check_statement(env, statement)


def check_statement(env: Env, statement: ast.Stmt) -> None:
    if isinstance(statement, ast.Block):
        check_block(env, statement)
    elif isinstance(statement, ast.CallStmt):
        type_, _ = calls.check_call(env, statement.call)
        call = statement.call
        acts = isinstance(call, ast.SelfCall) and call.name.text in ACTIONS
        if type_ is not None and type_ is not Type.VOID and not acts:
            env.ctx.report(codes.UNUSED_VALUE, call.span,
                           f"the {type_.value} value of '{call.name.text}' is unused; "
                           "use it in a condition or remove the call",
                           fixes=(diag.Fix("remove the statement",
                                           (diag.TextEdit(statement.span, ""),)),))
    elif isinstance(statement, ast.AssignStmt):
        states.check_assign(env, statement)
    elif isinstance(statement, ast.IfStmt):
        expressions.check_bool(env, statement.condition, "the condition of 'if'")
        check_statement(env, statement.then_body)
        if statement.else_body is not None:
            check_statement(env, statement.else_body)


def handler_env(env: Env) -> Env:
    """A handler block runs later, in the base role: assumed mixins do not apply to it."""
    return replace(env, mixins=(), in_assume=False, in_handler=True)


def warn_handler_in_assume(env: Env, call: ast.SelfCall | ast.FunctionCall) -> None:
    if env.method is not None:
        env.ctx.installs_handler.add(id(env.method))
    if env.in_assume:
        mixin = env.mixins[-1].name if env.mixins else "the mixin"
        env.ctx.report(codes.HANDLER_IN_ASSUME, call.name.span,
                       f"this handler is installed while playing '{mixin}' but runs later, in "
                       "whatever role the module then has; install it outside the assumeRole block")


def resolve_role_arg(env: Env, arg: ast.Arg) -> RoleSymbol | None:
    roles = env.ctx.model.roles
    if not isinstance(arg, ast.Block):
        arg = ast.unparen(arg)
    if not isinstance(arg, ast.NameRef):
        env.ctx.report(codes.ARG_TYPE, arg.span, "this argument must be a role name")
        if not isinstance(arg, ast.Block):
            expressions.check_expr(env, arg)
        return None
    name = arg.name.text
    role = roles.get(name)
    if role is not None:
        env.ctx.reference(arg.name, "role", name)
        return role
    if name:
        candidates = [r for r in roles if r != ROOT_ROLE]
        suffix, fixes = did_you_mean(name, candidates, arg.name.span)
        env.ctx.report(codes.UNKNOWN_ROLE, arg.name.span, f"unknown role '{name}'{suffix}",
                       fixes=fixes)
    return None


def check_assume_role(env: Env, call: ast.SelfCall | ast.FunctionCall) -> tuple[Type, Value | None]:
    target, block = call.args[0], call.args[1]
    if isinstance(target, ast.NameRef):
        mixin = resolve_role_arg(env, target)
    else:
        env.ctx.report(codes.NOT_A_MIXIN, target.span,
                       "the first argument of assumeRole must name a mixin role")
        mixin = None
    inner = replace(env, in_assume=True)
    if mixin is not None and not mixin.is_mixin:
        env.ctx.report(codes.NOT_A_MIXIN, target.span,
                       f"'{mixin.name}' is not a mixin; assumeRole needs a role declared "
                       f"'role M modifies {mixin.name} {{ … }}'")
    elif mixin is not None:
        env.ctx.assumed_mixins.setdefault(mixin.name, target.name)
        if env.method is not None:
            env.ctx.assumes.setdefault(id(env.method), set()).add(mixin.name)
        _check_applicable(env, mixin, target)
        if any(m.name == mixin.name for m in env.mixins):
            env.ctx.report(codes.NESTED_ASSUME, target.span,
                           f"the module already plays '{mixin.name}' here; remove this inner "
                           "assumeRole")
        else:
            inner = replace(inner, mixins=(*env.mixins, mixin))
    if isinstance(block, ast.Block):
        check_block(inner, block)
    else:
        env.ctx.report(codes.ARG_TYPE, block.span,
                       "the second argument of 'assumeRole' must be a block '{ … }'")
        expressions.check_expr(env, block)
    return Type.VOID, None


def _check_applicable(env: Env, mixin: RoleSymbol, target: ast.Arg) -> None:
    modified = mixin.modifies
    if modified is None or env.ctx.is_subrole(env.role.name, modified):
        return
    related = ()
    if mixin.decl is not None:
        related = (diag.Related(mixin.decl.name.span, f"'{mixin.name}' modifies '{modified}'"),)
    owner = "owns" if env.role is env.home else "inherits"
    env.ctx.report(codes.MIXIN_NOT_APPLICABLE, target.span,
                   f"mixin '{mixin.name}' modifies '{modified}', but '{env.role.name}' ({owner} "
                   f"this method) is not '{modified}' or a sub-role of it; move the method to "
                   f"'{modified}' or use a mixin of '{env.role.name}'",
                   related=related)
