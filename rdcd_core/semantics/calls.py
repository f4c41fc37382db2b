"""Calls: primitives of the Module API, functions, local methods and global commands (§5.1, §5.4)."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.module_api import (
    CONNECTOR_CALLS,
    FUNCTIONS,
    SELF_PRIMITIVES,
    Primitive,
    lookup_function,
    lookup_self,
)
from rdcd_core.semantics import codes, expressions, scoping, states
from rdcd_core.semantics.context import did_you_mean
from rdcd_core.semantics.env import Env
from rdcd_core.semantics.model import Value
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.types import Type

Result = tuple[Type | None, Value | None]


def check_call(env: Env, call: ast.Call) -> Result:
    if isinstance(call, ast.SelfCall):
        return _self_call(env, call)
    if isinstance(call, ast.FunctionCall):
        return _function_call(env, call)
    return _global_call(env, call)


def _self_call(env: Env, call: ast.SelfCall) -> Result:
    name = call.name.text
    primitive = lookup_self(name)
    if primitive is not None:
        env.ctx.reference(call.name, "primitive", name)
        if not call.has_parens and not primitive.is_query:
            _missing_parens(env, call, f"'{name}' is not a query; write 'self.{name}(…)'")
        if env.constant is not None:
            _not_constant(env, call)
            _check_args(env, call, primitive)
            return primitive.result, None
        return _check_args(env, call, primitive)
    method = env.lookup_method(name)
    if method is None:
        if name:
            candidates = [*SELF_PRIMITIVES, *env.method_names()]
            suffix, fixes = did_you_mean(name, candidates, call.name.span)
            env.ctx.report(codes.UNKNOWN_METHOD, call.name.span,
                           f"unknown primitive or method 'self.{name}'{suffix}", fixes=fixes)
        _check_extra_args(env, call.args)
        return None, None
    env.ctx.reference(call.name, "method", env.home_target(name, "method"))
    if not call.has_parens:
        _missing_parens(env, call, f"'{name}' is a method, not a query; write 'self.{name}()'")
    if env.constant is not None:
        _not_constant(env, call)
    _check_method_args(env, call, method.decl, f"method '{name}'")
    if method.kind is not ast.MethodKind.PLAIN:
        hint = f"call it with '{method.owner}.{name}()'" if method.kind is ast.MethodKind.COMMAND \
            else "only plain methods can be called; move the code into a plain method"
        env.ctx.report(codes.NOT_PLAIN, call.name.span,
                       f"'{name}' is a {method.kind.value} method and cannot be called with "
                       f"self.{name}(); {hint}",
                       related=(diag.Related(method.decl.name.span, f"'{name}' is declared here"),))
    else:
        if env.method is not None:
            edges = env.ctx.call_edges.setdefault(id(env.method), [])
            edges.append((method.decl, call.name))
            env.ctx.methods_by_id[id(env.method)] = env.method
        if env.mixins or env.in_assume:
            played = tuple(m.name for m in env.mixins)
            env.ctx.inlined.append((method.decl, call.name, played, env.in_assume))
    return Type.VOID, None


def _missing_parens(env: Env, call: ast.SelfCall, message: str) -> None:
    end = call.name.span.end
    env.ctx.report(codes.MISSING_PARENS, call.name.span, message,
                   fixes=(diag.Fix("add '()'", (diag.TextEdit(Span(end, end), "()"),)),))


def _not_constant(env: Env, call: ast.Call) -> None:
    env.ctx.report(codes.NOT_CONSTANT, call.span,
                   f"constant '{env.constant}' must be constant-foldable, but "
                   f"'{call.name.text}' is computed at run time; use a literal, a predefined "
                   "value or another constant")


def _function_call(env: Env, call: ast.FunctionCall) -> Result:
    name = call.name.text
    function = lookup_function(name)
    if function is None:
        if name in SELF_PRIMITIVES:
            fix = diag.Fix(f"write 'self.{name}'",
                           (diag.TextEdit(Span(call.name.span.start, call.name.span.start), "self."),))
            env.ctx.report(codes.UNKNOWN_FUNCTION, call.name.span,
                           f"'{name}' is a primitive of the module; write 'self.{name}(…)'",
                           fixes=(fix,))
        elif name:
            suffix, fixes = did_you_mean(name, FUNCTIONS, call.name.span)
            env.ctx.report(codes.UNKNOWN_FUNCTION, call.name.span,
                           f"unknown function '{name}'{suffix}" +
                           ("" if suffix else "; the functions are " + ", ".join(FUNCTIONS)),
                           fixes=fixes)
        _check_extra_args(env, call.args)
        return None, None
    env.ctx.reference(call.name, "primitive", name)
    if env.constant is not None:
        _not_constant(env, call)
        _check_args(env, call, function)
        return function.result, None
    return _check_args(env, call, function)


def _global_call(env: Env, call: ast.GlobalCall) -> Result:
    roles = env.ctx.model.roles
    role = roles.get(call.role.text)
    if env.constant is not None:
        _not_constant(env, call)
    if role is None:
        if call.role.text:
            suffix, fixes = did_you_mean(call.role.text, roles, call.role.span)
            env.ctx.report(codes.UNKNOWN_ROLE, call.role.span,
                           f"unknown role '{call.role.text}'{suffix}", fixes=fixes)
        _check_extra_args(env, call.args)
        return Type.VOID, None
    env.ctx.reference(call.role, "role", role.name)
    env.ctx.observed_roles.setdefault(role.name, call.role)
    name = call.name.text
    method = role.methods.get(name)
    commands = [m for m, s in role.methods.items() if s.kind is ast.MethodKind.COMMAND]
    if method is None:
        suffix, fixes = did_you_mean(name, commands, call.name.span)
        hint = "" if suffix else "; call a role that declares it" if role.decl is None else \
            f"; declare 'command {name}() {{ … }}' in '{role.name}'"
        env.ctx.report(codes.BAD_GLOBAL_CALL, call.name.span,
                       f"role '{role.name}' has no command '{name}'{suffix}{hint}", fixes=fixes)
    elif method.kind is not ast.MethodKind.COMMAND:
        env.ctx.reference(call.name, "method", f"{method.owner}.{name}")
        env.ctx.report(codes.BAD_GLOBAL_CALL, call.name.span,
                       f"'{role.name}.{name}' is a {method.kind.value} method, not a command; "
                       f"declare it 'command' or call it with self.{name}()",
                       related=(diag.Related(method.decl.name.span, f"'{name}' is declared here"),))
    else:
        env.ctx.reference(call.name, "command", f"{method.owner}.{name}")
    if method is not None and method.kind is ast.MethodKind.COMMAND:
        _check_method_args(env, call, method.decl, f"command '{role.name}.{name}'")
    else:
        _check_extra_args(env, call.args)
    return Type.VOID, None


def _check_method_args(env: Env, call: ast.SelfCall | ast.GlobalCall, decl: ast.MethodDecl,
                       what: str) -> None:
    """Arguments of a method or command: as many as it has parameters, each an int."""
    params = decl.params
    if len(call.args) != len(params):
        wanted = "no arguments" if not params else \
            f"{len(params)} argument{'s' if len(params) != 1 else ''} ({', '.join(p.text for p in params)})"
        env.ctx.report(codes.ARG_COUNT, call.span, f"{what} takes {wanted}, not {len(call.args)}")
    for index, arg in enumerate(call.args):
        if index >= len(params) or isinstance(arg, ast.Block):
            _check_extra_args(env, (arg,))
            continue
        type_, _ = expressions.check_expr(env, arg)
        if type_ is not None and type_ is not Type.INT:
            env.ctx.report(codes.ARG_TYPE, arg.span,
                           f"argument '{params[index].text}' of {what} must be an int, not "
                           f"{expressions.a_type(type_)}")


def _check_extra_args(env: Env, args: tuple[ast.Arg, ...]) -> None:
    """Checks arguments that have no parameter (for their own errors and references)."""
    for arg in args:
        if isinstance(arg, ast.Block):
            env.ctx.report(codes.BLOCK_NOT_ALLOWED, arg.span,
                           "a block is allowed only as the second argument of handleEvent or "
                           "assumeRole")
            scoping.check_block(env, arg)
        elif isinstance(arg, ast.NameRef) and arg.name.text in env.ctx.model.roles:
            env.ctx.reference(arg.name, "role", arg.name.text)
        else:
            expressions.check_expr(env, arg)


def _check_args(env: Env, call: ast.SelfCall | ast.FunctionCall, primitive: Primitive) -> Result:
    params = primitive.params
    args = call.args
    if len(args) == 1 and isinstance(ast.unparen(args[0]), ast.NeighbourValues) and (
            primitive.aggregate or (params and params[0].type is Type.VALUES)):
        states.check_values(env, ast.unparen(args[0]))  # type: ignore[arg-type]
        return primitive.result, None
    if primitive.variadic and len(args) >= len(params):
        return _check_table(env, primitive, args)
    if len(args) != len(params):
        expected = ("at least " if primitive.variadic else "") + \
            f"{len(params)} argument{'s' if len(params) != 1 else ''}"
        env.ctx.report(codes.ARG_COUNT, call.span,
                       f"'{primitive.name}' takes {expected}, not {len(args)}: {primitive.signature}")
    if primitive.name == "assumeRole" and len(args) == 2:
        return scoping.check_assume_role(env, call)
    if primitive.name == "handleEvent" and len(args) == 2:
        scoping.warn_handler_in_assume(env, call)
    values: list[Value | None] = []
    for index, arg in enumerate(args):
        if index >= len(params):
            _check_extra_args(env, (arg,))
            continue
        values.append(_check_arg(env, primitive, index, arg))
    if primitive.values is not None and values and values[0] is not None:
        _check_range(env, primitive, args[0], values[0].value)
    if primitive.name in CONNECTOR_CALLS and values and values[0] is not None:
        _check_connector(env, primitive.name, args[0], values[0].value)
    return primitive.result, None


def _check_arg(env: Env, primitive: Primitive, index: int, arg: ast.Arg) -> Value | None:
    param = primitive.params[index]
    if param.type is Type.BLOCK:
        if not isinstance(arg, ast.Block):
            env.ctx.report(codes.ARG_TYPE, arg.span,
                           f"argument '{param.name}' of '{primitive.name}' must be a block '{{ … }}'")
            _check_extra_args(env, (arg,))
            return None
        handler = primitive.name == "handleEvent"
        scoping.check_block(scoping.handler_env(env) if handler else env, arg)
        return None
    if isinstance(arg, ast.Block):
        _check_extra_args(env, (arg,))
        return None
    if primitive.degrees and index == 0:
        written = ast.signed_literal(arg)  # an angle written as a number: degrees, not a value
        if written is not None and abs(written) < 10**18:
            return Value(Type.INT, written)
    if param.type is Type.ROLE:
        role = scoping.resolve_role_arg(env, arg)
        if role is not None and primitive.name == "connected_role":
            env.ctx.observed_roles.setdefault(role.name, ast.unparen(arg).name)  # type: ignore[union-attr]
        return None
    type_, value = expressions.check_expr(env, arg)
    if type_ is not None and type_ is not param.type:
        where = expressions.where(env, arg)
        where = f" ({where.strip()})" if where else ""
        env.ctx.report(codes.ARG_TYPE, arg.span,
                       f"argument '{param.name}' of '{primitive.name}' must be "
                       f"{expressions.a_type(param.type)}, not {expressions.a_type(type_)}{where}: "
                       f"{primitive.signature}")
        return None
    return value


def _check_connector(env: Env, name: str, arg: ast.Arg, connector: int) -> None:
    """A constant connector that no ATRON connector is, or a female one asked to latch or unlatch
    (only male connectors, even numbers, have the hooks: atron.h, docs/module-api.md)."""
    where = expressions.where(env, arg)
    if not 0 <= connector <= 7:
        env.ctx.report(codes.CONNECTOR_NEVER_LATCHES, arg.span,
                       f"'{name}' needs a physical connector 0..7, but this is {connector}{where}")
    elif name in ("connect", "disconnect") and connector % 2:
        env.ctx.report(codes.CONNECTOR_NEVER_LATCHES, arg.span,
                       f"connector {connector}{where} is female (odd): only a male connector (even) can "
                       f"{name}; use {connector - 1} or {(connector + 1) % 8}, or have the neighbour's male "
                       "connector act")



def _check_table(env: Env, primitive: Primitive, args: tuple) -> Result:
    """table(i, v0, ...): an index known at run time and constants 0..127 (one byte each)."""
    _check_arg(env, primitive, 0, args[0])
    low, high, _ = primitive.values  # type: ignore[misc]
    for arg in args[1:]:
        value = _check_arg(env, primitive, 1, arg)
        if isinstance(arg, ast.Block):
            continue
        if value is None:
            env.ctx.report(codes.NOT_CONSTANT, arg.span,
                           f"the values of '{primitive.name}' must be constants {low}..{high}")
        elif not low <= value.value <= high:
            env.ctx.report(codes.BAD_JOINT_VALUE, arg.span,
                           f"'{primitive.name}' holds values {low}..{high} (one byte each), not "
                           f"{value.value}{expressions.where(env, arg)}")
    return primitive.result, None


def _check_range(env: Env, primitive: Primitive, arg: ast.Arg, value: int) -> None:
    """A constant argument outside the values the joint takes (module_api's ``values``; the VM
    checks a value known only at run time against the same range)."""
    low, high, step = primitive.values  # type: ignore[misc]
    if value % step == 0 and low <= value <= high:
        return
    where = expressions.where(env, arg)
    name = primitive.name
    if step != 1:
        span = "" if name == "turnDegrees" else f" in {low}..{high}"
        env.ctx.report(codes.BAD_ANGLE, arg.span,
                       f"'{name}' needs a multiple of {step} degrees{span}, but this is {value}{where}")
    else:
        what = "a speed" if name == "turnContinuously" else "a number of turns"
        env.ctx.report(codes.BAD_JOINT_VALUE, arg.span,
                       f"'{name}' needs {what} in {low}..{high}, but this is {value}{where}")
