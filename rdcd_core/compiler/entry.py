"""What a module does when it takes a concrete role: install the role's commands, run its
startup methods, start its behaviours. Each piece is an ``EntryItem``, the unit of splitting.

A behaviour is installed as a program in the role's command table (after the user commands) and
started with EVAL_COMMAND; its body ends with END_REPEAT, so it repeats on that module while the
fragment that carried it migrates on.
"""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.exprgen import emit
from rdcd_core.compiler.ir import Body, Item, Label
from rdcd_core.compiler.roletable import application_name
from rdcd_core.compiler.stmtgen import body_of, statement, statements
from rdcd_core.semantics.model import MethodSymbol, Model, RoleSymbol
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from vm.isa.opcodes import USER_COMMAND_BASE


@dataclass(slots=True)
class EntryItem:
    kind: str  # command | startup | behavior
    code: list[Item]
    span: Span
    method: str = ""
    stmt: ast.Stmt | None = None  # the startup statement it came from (for splitting)
    # a command or behaviour (for splitting into a chain, rdcd_core.compiler.chain): its method,
    # its command number, the role id it is installed for, whether a behaviour checks its role
    # first and whether it waits for values (END_WAIT)
    symbol: MethodSymbol | None = None
    number: int = 0
    install_role: int = 0
    check: bool = False
    reactive: bool = False
    mixin: str = ""  # a mixin's command: the mixin whose members overlay the role's


def assign_command_numbers(model: Model) -> dict[str, int]:
    """User command k of every command name; a name keeps one k in every role that has it.
    A mixin's commands share the table of the roles it applies to."""
    numbers: dict[str, int] = {}
    having: dict[str, list[RoleSymbol]] = {}  # method name -> the roles that have it
    for role in model.roles.values():
        for name in role.methods:
            having.setdefault(name, []).append(role)
    subroles: dict[str, list[str]] = {}
    symbols = sorted(model.roles.values(), key=lambda s: s.is_mixin)
    for symbol in symbols:
        for method in symbol.methods.values():
            if method.kind is not ast.MethodKind.COMMAND or method.name in numbers:
                continue
            sharing = list(having[method.name])
            if symbol.is_mixin and symbol.modifies:
                if symbol.modifies not in subroles:
                    subroles[symbol.modifies] = model.subroles(symbol.modifies)
                sharing += [model.roles[r] for r in subroles[symbol.modifies]]
            taken = {numbers[m] for r in sharing for m in r.methods if m in numbers}
            # past the table (64) only with more commands than E121 allows; command_limit reports it
            numbers[method.name] = next((k for k in range(64) if k not in taken), 64)
    return numbers


def methods_of(model: Model, role: str, kind: ast.MethodKind) -> list[MethodSymbol]:
    return [m for m in model.roles[role].methods.values()
            if m.kind is kind and m.decl.body is not None]


def behaviour_numbers(model: Model, role: str, commands: dict[str, int]) -> dict[str, int]:
    used = {commands[m.name] for m in methods_of(model, role, ast.MethodKind.COMMAND)}
    numbers: dict[str, int] = {}
    for method in methods_of(model, role, ast.MethodKind.BEHAVIOR):
        numbers[method.name] = min(k for k in range(64) if k not in used)
        used.add(numbers[method.name])
    return numbers


def entry_items(ctx: Context, needs_role_check: bool) -> list[EntryItem]:
    model, role = ctx.model, ctx.role
    role_id = ctx.table.id_of(role) or 0
    items: list[EntryItem] = []
    items += _role_state_items(ctx)
    for method in methods_of(model, role, ast.MethodKind.COMMAND):
        number = USER_COMMAND_BASE + ctx.command_numbers[method.name]
        body = _command_body(method, ctx)
        code: list[Item] = []
        emit(code, "INSTALL_COMMAND", role_id, number, body, span=method.decl.name.span)
        items.append(EntryItem("command", code, method.decl.span, method.name, symbol=method,
                               number=number, install_role=role_id))
    items += _mixin_commands(ctx)
    for method in methods_of(model, role, ast.MethodKind.STARTUP):
        for stmt in method.decl.body.statements:
            items += startup_items(stmt, ctx, method.name)
    numbers = behaviour_numbers(model, role, ctx.command_numbers)
    for method in methods_of(model, role, ast.MethodKind.BEHAVIOR):
        number = USER_COMMAND_BASE + numbers[method.name]
        check = needs_role_check or (ctx.watched and not _shared_by_every_role(method, ctx))
        body = _behaviour_body(method, ctx, role_id, check)
        code = []
        if ctx.watched:  # started again whenever the role is taken again: RUN_LOCAL keeps one copy
            emit(code, "RUN_LOCAL", body, span=method.decl.name.span)
        else:
            emit(code, "INSTALL_COMMAND", role_id, number, body, span=method.decl.name.span)
            emit(code, "EVAL_COMMAND", number, 0, span=method.decl.name.span)
        reactive = ctx.has("END_WAIT") and reacts_only_to_values(method.decl.body)
        items.append(EntryItem("behavior", code, method.decl.span, method.name, symbol=method,
                               number=number, install_role=role_id, check=check, reactive=reactive))
    return items


def _shared_by_every_role(method: MethodSymbol, ctx: Context) -> bool:
    """A behaviour that every deployed role inherits from one declaration and whose code reads no
    constant is the same code on every role: one copy serves whichever role a module takes, so it
    needs no role check (RUN_LOCAL keeps one copy of the same code)."""
    model = ctx.model
    if any(model.roles[r].methods.get(method.name) is None
           or model.roles[r].methods[method.name].decl is not method.decl for r in model.deployment):
        return False
    return not any(isinstance(node, ast.NameRef) and ctx.constant_symbol(node.name.text)
                   for node in ast.walk(method.decl.body))


def _command_body(method: MethodSymbol, ctx: Context) -> Body:
    """A command's body; its parameter reads the argument the command was sent with."""
    saved, params = (ctx.argument, ctx.command), method.decl.params
    ctx.argument, ctx.command = (params[0].text if params else None), method.name
    try:
        return body_of(method.decl.body, ctx, "END_TERMINATE")
    finally:
        ctx.argument, ctx.command = saved


def _role_state_items(ctx: Context) -> list[EntryItem]:
    """Role state back to its initial value when the module takes the role (a value that is
    already right is not stored: 0 at the start, unless roles are re-taken as values change)."""
    items: list[EntryItem] = []
    for state in ctx.model.roles[ctx.role].states.values():
        if state.initial == 0 and not ctx.watched:
            continue
        code: list[Item] = []
        emit(code, "PUSH", state.initial, span=state.decl.span)
        ctx.need("STORE_STATE", state.decl.span, "state needs the extension instruction")
        emit(code, "STORE_STATE", state.index, span=state.decl.span)
        items.append(EntryItem("startup", code, state.decl.span, state.name))
    return items


def reacts_only_to_values(block: ast.Block) -> bool:
    """Whether a behaviour's body computes only from values (state, neighbours' values and roles,
    coordinates, connections) and only assigns state: running it again changes nothing until one
    of those values changes, so it waits for a change (END_WAIT) instead of repeating."""
    for node in ast.walk(block):
        if isinstance(node, ast.GlobalCall):
            return False
        if isinstance(node, ast.SelfCall) and node.name.text not in _PURE_QUERIES:
            return False
    return any(isinstance(node, ast.AssignStmt) for node in ast.walk(block))


_PURE_QUERIES = frozenset({"center_position", "total_connected", "connected", "x", "y", "z"})


def startup_items(stmt: ast.Stmt, ctx: Context, method: str) -> list[EntryItem]:
    code: list[Item] = []
    statement(stmt, ctx, code)
    return [EntryItem("startup", code, stmt.span, method, stmt)] if code else []


def split_statement(stmt: ast.Stmt | None) -> list[ast.Stmt]:
    """A startup statement as smaller statements with the same effect, run one after the other:
    a block as its statements; ``if (c) {A; B} else {C}`` as ``if (c) A; if (c) B; if (!c) C``
    when ``c`` reads only what cannot change meanwhile (coordinates, axis, connections: not the
    neighbours' roles). [] when it cannot be split."""
    if isinstance(stmt, ast.Block):
        return list(stmt.statements) if len(stmt.statements) > 1 else split_statement(
            stmt.statements[0] if stmt.statements else None)
    if not isinstance(stmt, ast.IfStmt) or not _stable(stmt.condition):
        return []
    parts = [ast.IfStmt(stmt.condition, s, None, s.span) for s in _flat(stmt.then_body)]
    if stmt.else_body is not None:
        negated = ast.Unary("!", stmt.condition, stmt.condition.span)
        parts += [ast.IfStmt(negated, s, None, s.span) for s in _flat(stmt.else_body)]
    return parts if len(parts) > 1 else []


def _flat(stmt: ast.Stmt) -> list[ast.Stmt]:
    return list(stmt.statements) if isinstance(stmt, ast.Block) else [stmt]


def _stable(expr: ast.Node) -> bool:
    return not any(isinstance(node, ast.FunctionCall) and node.name.text == "connected_role"
                   for node in ast.walk(expr))


def _behaviour_body(method: MethodSymbol, ctx: Context, role_id: int, check: bool) -> Body:
    saved, ctx.in_body = ctx.in_body, True
    try:
        return _behaviour_code(method, ctx, role_id, check)
    finally:
        ctx.in_body = saved


def _behaviour_code(method: MethodSymbol, ctx: Context, role_id: int, check: bool) -> Body:
    code: list[Item] = []
    end = Label("repeat")
    if check:
        emit(code, "HAS_ROLE", role_id, span=method.decl.name.span)
        emit(code, "IF_FALSE_GOTO", end, span=method.decl.name.span)
    statements(method.decl.body.statements, ctx, code)
    code.append(end)
    reactive = ctx.has("END_WAIT") and reacts_only_to_values(method.decl.body)
    emit(code, "END_WAIT" if reactive else "END_REPEAT", span=method.decl.span)
    return Body(code)


def _mixin_commands(ctx: Context) -> list[EntryItem]:
    """Commands of a mixin M, installed for M applied to this role (after the role's own, which
    they override while the module plays M)."""
    items: list[EntryItem] = []
    for mixin in ctx.model.mixins_of(ctx.role):
        applied = ctx.table.id_of(application_name(mixin, ctx.role))
        if applied is None:
            continue
        ctx.mixins.append(mixin)
        for method in methods_of(ctx.model, mixin, ast.MethodKind.COMMAND):
            number = USER_COMMAND_BASE + ctx.command_numbers[method.name]
            body = _command_body(method, ctx)
            code: list[Item] = []
            emit(code, "INSTALL_COMMAND", applied, number, body, span=method.decl.name.span)
            items.append(EntryItem("command", code, method.decl.span, method.name, symbol=method,
                                   number=number, install_role=applied, mixin=mixin))
        ctx.mixins.pop()
    return items
