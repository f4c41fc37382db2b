"""State (language reference, "State"): declarations, initial values, reads, assignments, the
neighbours' values and the layout of a module's state memory.

Module state is declared at the top level and kept across role changes; role state is declared
in a role, inherited by its sub-roles, and set to its initial value whenever the module takes
the role. Names resolve innermost first: a parameter of the enclosing command or method, then
the role's constants and role state, then module state, then the predefined values.
"""

from __future__ import annotations

from dataclasses import replace

from rdcd_core import diagnostics as diag
from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context, did_you_mean
from rdcd_core.semantics.env import Env
from rdcd_core.semantics.model import ROOT_ROLE, StateSymbol, Value
from rdcd_core.syntax import ast
from rdcd_core.types import PREDEFINED_VALUES, Type

STATE_BYTES = 32  # state a module holds (vm.isa.opcodes.STATE_SLOTS)
PUBLISHED_STATES = 8  # module states neighbours can read (vm.isa.opcodes.PUBLISHED_SLOTS)
AGGREGATES = ("min", "max", "count", "sum")


def declare_module_states(ctx: Context) -> None:
    for decl in ctx.model.program.states:
        name = decl.name.text
        if not name:
            continue
        first = ctx.model.states.get(name)
        if first is not None:
            ctx.report(codes.DUPLICATE_STATE, decl.name.span,
                       f"module state '{name}' is already declared; rename or remove one",
                       related=(diag.Related(first.decl.name.span, f"first declaration of '{name}'"),))
            continue
        ctx.model.states[name] = StateSymbol(name, None, decl, travelling=decl.travelling)
        ctx.reference(decl.name, "state", name, True)
        travelling = [s for s in ctx.model.states.values() if s.travelling]
        if decl.travelling and len(travelling) > 1:
            ctx.report(codes.BAD_TRAVELLING, decl.name.span,
                       f"'{name}' is a second travelling state; a program carries one value, "
                       f"'{travelling[0].name}'",
                       related=(diag.Related(travelling[0].decl.name.span, "the travelling state"),))
            ctx.model.states[name].travelling = False


def role_state(ctx: Context, role: str, decl: ast.StateDecl) -> StateSymbol:
    ctx.reference(decl.name, "state", f"{role}.{decl.name.text}", True)
    if decl.travelling:
        ctx.report(codes.BAD_TRAVELLING, decl.span,
                   f"only module state travels: declare 'travelling state {decl.name.text} := …;' at the "
                   "top level of the program")
    return StateSymbol(decl.name.text, role, decl)


def state_target(symbol: StateSymbol) -> str:
    return symbol.name if symbol.owner is None else f"{symbol.owner}.{symbol.name}"


def fold_initials(ctx: Context) -> None:
    """Every state's initial value: a constant int (constants of its role may be used)."""
    from rdcd_core.semantics import expressions

    roles = ctx.model.roles
    for symbol in ctx.model.all_states():
        role = roles.get(symbol.owner or ROOT_ROLE) or roles[ROOT_ROLE]
        env = Env(ctx, role, role, constant=symbol.name)
        type_, value = expressions.check_expr(env, symbol.decl.value)
        if type_ is None:
            continue
        if type_ is not Type.INT or value is None:
            ctx.report(codes.BAD_INITIAL_VALUE, symbol.decl.value.span,
                       f"the initial value of state '{symbol.name}' must be a constant int"
                       + ("" if type_ is Type.INT else f", not {expressions.a_type(type_)}")
                       + "; assign computed values in a method")
            continue
        symbol.initial = value.value


def lookup(env: Env, name: str) -> StateSymbol | None:
    """The state ``name`` names in ``env`` (role state of the role played, else module state)."""
    found = env.role.states.get(name)
    if found is not None:
        return found
    return env.ctx.model.states.get(name)


def parameter(env: Env, name: str) -> ast.Name | None:
    method = env.method
    if method is None:
        return None
    for param in method.params:
        if param.text == name:
            return param
    return None


def read(env: Env, expr: ast.NameRef) -> tuple[Type | None, Value | None] | None:
    """The type of a state or parameter read by ``expr``; None when ``name`` is neither."""
    name = expr.name.text
    param = parameter(env, name)
    if param is not None:
        if env.in_handler:
            env.ctx.report(codes.UNKNOWN_NAME, expr.name.span,
                           f"parameter '{name}' is not available in a handler: the handler runs later, "
                           "without it; copy it into a state first")
            return None, None
        env.ctx.reference(expr.name, "parameter", _param_target(env, name))
        if env.constant is not None:
            return Type.INT, None
        return Type.INT, None
    if env.lookup_constant(name)[0] is not None:
        return None
    symbol = lookup(env, name)
    if symbol is None:
        return _other_roles_state(env, expr.name, "read")
    env.ctx.reference(expr.name, "state", state_target(symbol))
    env.ctx.read_states.add(id(symbol))
    if env.constant is not None:
        env.ctx.report(codes.NOT_CONSTANT, expr.span,
                       f"'{env.constant}' must be constant-foldable, but state '{name}' changes at run "
                       "time; use a literal, a predefined value or a constant")
    return Type.INT, None


def _role_state_owners(ctx: Context) -> dict[str, str]:
    """Role state name -> the first role that declares it (computed once per analysis)."""
    if ctx.role_state_owners is None:
        owners: dict[str, str] = {}
        for role in ctx.model.roles.values():
            for state in role.states.values():
                if state.owner == role.name:
                    owners.setdefault(state.name, role.name)
        ctx.role_state_owners = owners
    return ctx.role_state_owners


def _param_target(env: Env, name: str) -> str:
    method = env.method
    return f"{env.home.name}.{method.name.text if method else ''}.{name}"


def _other_roles_state(env: Env, name: ast.Name, what: str) -> tuple[None, None] | None:
    owner = _role_state_owners(env.ctx).get(name.text)
    if owner is None:
        return None
    symbol = env.ctx.model.roles[owner].states[name.text]
    env.ctx.reference(name, "state", state_target(symbol))
    env.ctx.report(codes.OTHER_ROLES_STATE, name.span,
                   f"state '{name.text}' belongs to role '{owner}': only the code of '{owner}' and its "
                   f"sub-roles can {what} it; declare it at the top level to share it between roles",
                   related=(diag.Related(symbol.decl.name.span, f"'{name.text}' is declared here"),))
    return None, None


def check_assign(env: Env, stmt: ast.AssignStmt) -> None:
    from rdcd_core.semantics import expressions

    name = stmt.name.text
    if isinstance(stmt.value, ast.Block):
        env.ctx.report(codes.BLOCK_NOT_ALLOWED, stmt.value.span,
                       "a block is not a value: a state holds an int; blocks are allowed only as the "
                       "second argument of handleEvent or assumeRole")
        type_ = None
    else:
        type_, _ = expressions.check_expr(env, stmt.value)
    if type_ is not None and type_ is not Type.INT:
        env.ctx.report(codes.TYPE_MISMATCH, stmt.value.span,
                       f"a state holds an int, not {expressions.a_type(type_)}")
    if not name:
        return
    if parameter(env, name) is not None:
        env.ctx.report(codes.NOT_A_STATE, stmt.name.span,
                       f"'{name}' is a parameter, which cannot be assigned; declare a state for the value")
        return
    constant, _ = env.lookup_constant(name)
    if constant is not None:
        env.ctx.reference(stmt.name, "constant", env.home_target(name, "constant"))
        env.ctx.report(codes.NOT_A_STATE, stmt.name.span,
                       f"'{name}' is a constant, which cannot be assigned; declare 'state {name} := …;' "
                       "instead",
                       related=(diag.Related(constant.declaration.span, f"'{name}' is declared here"),))
        return
    symbol = lookup(env, name)
    if symbol is not None:
        env.ctx.reference(stmt.name, "state", state_target(symbol))
        env.ctx.written_states.add(id(symbol))
        return
    if _other_roles_state(env, stmt.name, "assign") is not None:
        return
    if name in PREDEFINED_VALUES or name in env.ctx.model.roles:
        env.ctx.report(codes.NOT_A_STATE, stmt.name.span,
                       f"'{name}' is a {'predefined value' if name in PREDEFINED_VALUES else 'role'}, "
                       "which cannot be assigned")
        return
    candidates = [*env.role.states, *env.ctx.model.states]
    suffix, fixes = did_you_mean(name, candidates, stmt.name.span)
    env.ctx.report(codes.UNKNOWN_STATE, stmt.name.span,
                   f"unknown state '{name}'{suffix}" + ("" if suffix else
                                                        f"; declare it: 'state {name} := 0;'"),
                   fixes=fixes)


def check_values(env: Env, expr: ast.NeighbourValues) -> Type | None:
    """``neighbours.s`` as an aggregate's argument: ``s`` must be module state."""
    from rdcd_core.semantics import expressions

    if expr.where is not None:
        type_, value = expressions.check_expr(env, expr.where)
        if type_ is Type.DIR:
            pass
        elif type_ is Type.INT and value is not None and 0 <= value.value <= 7:
            pass
        elif type_ is not None:
            shown = f"{value.value}" if value is not None else f"{expressions.a_type(type_)}"
            env.ctx.report(codes.BAD_NEIGHBOUR_FILTER, expr.where.span,
                           f"neighbours(...) takes a direction (UP, EAST, …) or a constant connector "
                           f"number 0..7, not {shown}")
    name = expr.name.text
    symbol = env.ctx.model.states.get(name)
    if symbol is None:
        role_symbol = lookup(env, name)
        if role_symbol is not None:
            env.ctx.reference(expr.name, "state", state_target(role_symbol))
            env.ctx.report(codes.NOT_PUBLISHED, expr.name.span,
                           f"'{name}' is role state; neighbours publish only module state: declare "
                           f"'state {name} := …;' at the top level")
            return None
        what = "a constant" if env.lookup_constant(name)[0] is not None else "not a state"
        suffix, fixes = did_you_mean(name, env.ctx.model.states, expr.name.span)
        env.ctx.report(codes.NOT_PUBLISHED, expr.name.span,
                       f"'{name}' is {what}; neighbours publish module state only{suffix}", fixes=fixes)
        return None
    env.ctx.reference(expr.name, "state", state_target(symbol))
    env.ctx.read_states.add(id(symbol))
    symbol.published = True
    if env.constant is not None:
        env.ctx.report(codes.NOT_CONSTANT, expr.span,
                       f"'{env.constant}' must be constant-foldable, but neighbours' values change at "
                       "run time")
    return Type.VALUES


def check_parameters(ctx: Context) -> None:
    """Parameters: plain names, distinct, at most one for a command (the packet's argument byte),
    none for startup and behaviour methods; a parameter that hides a constant or state is W701."""
    for role in ctx.model.roles.values():
        if role.decl is None:
            continue
        for member in role.decl.members:
            if not isinstance(member, ast.MethodDecl):
                continue
            for span in member.bad_params:
                ctx.report(codes.BAD_PARAMETER, span, "a parameter must be a name")
            kind = member.kind
            limit = 1 if kind is ast.MethodKind.COMMAND else 0 if kind in (
                ast.MethodKind.STARTUP, ast.MethodKind.BEHAVIOR) else 8
            seen: dict[str, ast.Name] = {}
            for index, param in enumerate(member.params):
                ctx.reference(param, "parameter", f"{role.name}.{member.name.text}.{param.text}", True)
                if param.text in seen:
                    ctx.report(codes.BAD_PARAMETER, param.span, f"parameter '{param.text}' is declared twice",
                               related=(diag.Related(seen[param.text].span, "first declaration"),))
                seen[param.text] = param
                if index >= limit:
                    why = ("a command takes at most one parameter: its packet carries one argument byte"
                           if kind is ast.MethodKind.COMMAND else
                           f"a {kind.value} method takes no parameters: nothing calls it with arguments")
                    ctx.report(codes.BAD_PARAMETER, param.span, why)
                hidden = role.constants.get(param.text) or role.states.get(param.text) \
                    or ctx.model.states.get(param.text)
                if hidden is not None:
                    ctx.report(codes.SHADOWS, param.span,
                               f"parameter '{param.text}' hides the {_what(hidden)} '{param.text}' in "
                               f"'{member.name.text}'; rename it")


def _what(symbol: object) -> str:
    if isinstance(symbol, StateSymbol):
        return "module state" if symbol.owner is None else "role state"
    return "constant"


def check_shadowing(ctx: Context) -> None:
    """Role state and constants that hide module state of the same name (W701)."""
    module = ctx.model.states
    if not module:
        return
    for role in ctx.model.roles.values():
        if role.decl is None:
            continue
        for member in role.decl.members:
            name = member.name if isinstance(member, (ast.StateDecl, ast.ConstantDef)) else None
            if name is not None and name.text in module:
                what = "role state" if isinstance(member, ast.StateDecl) else "constant"
                ctx.report(codes.SHADOWS, name.span,
                           f"{what} '{name.text}' of '{role.name}' hides the module state '{name.text}' "
                           f"in that role; rename one",
                           related=(diag.Related(module[name.text].decl.name.span, "the module state"),))


def layout(ctx: Context) -> None:
    """Bytes of the state memory: published module state in 0..7 (the VM sends those to the
    neighbours on every change), the rest from 8 on, so that a state no neighbour reads is never
    sent; reports what does not fit (E720) and states never read (W702)."""
    states = ctx.model.all_states()
    published = [s for s in states if s.published]
    rest = [s for s in states if not s.published]
    for index, symbol in enumerate(published):
        symbol.index = index
    for index, symbol in enumerate(rest, start=PUBLISHED_STATES):
        symbol.index = index
    if len(published) > PUBLISHED_STATES:
        extra = published[PUBLISHED_STATES]
        ctx.report(codes.STATE_TOO_MANY, extra.decl.name.span,
                   f"{len(published)} module states are read by neighbours; the VM keeps the values of "
                   f"at most {PUBLISHED_STATES} per neighbour")
    if len(rest) > STATE_BYTES - PUBLISHED_STATES:
        extra = rest[STATE_BYTES - PUBLISHED_STATES]
        ctx.report(codes.STATE_TOO_MANY, extra.decl.name.span,
                   f"{len(states)} states are declared, {len(rest)} of them not read by neighbours; a "
                   f"module holds {STATE_BYTES} bytes of state, {PUBLISHED_STATES} of them for states "
                   f"the neighbours read, so at most {STATE_BYTES - PUBLISHED_STATES} others")
    progress = {seq.name.span for seq in ctx.model.program.sequences}  # read by the generated code
    for symbol in states:
        if id(symbol) not in ctx.read_states and symbol.decl.name.text and symbol.decl.span not in progress:
            ctx.report(codes.UNUSED_STATE, symbol.decl.name.span,
                       f"state '{symbol.name}' is never read; remove it or use it")


def handler_scope(env: Env) -> Env:
    return replace(env, in_handler=True)
