"""Code for statements and calls: primitives, local method inlining, global commands,
``handleEvent`` and ``assumeRole`` (role switch, body, restore)."""

from __future__ import annotations

from rdcd_core.compiler import codes, connectors
from rdcd_core.compiler.compare import is_nonnegative
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.exprgen import cjump, const_arg, emit, value
from rdcd_core.compiler.fold import fold
from rdcd_core.compiler.ir import Body, Ins, Item, Label
from rdcd_core.compiler.known import known_values, literal
from rdcd_core.compiler.roletable import application_name
from rdcd_core.module_api import lookup_self
from rdcd_core.syntax import ast
from rdcd_core.syntax.builder import MAX_HEIGHT
from vm.isa.opcodes import ROTATE_CCW, ROTATE_CW, ROTATE_DEGREES, ROTATE_TO, STOP, USER_COMMAND_BASE

QUERIES = {"center_position", "total_connected", "connected", "x", "y", "z"}
EVENT_OPS = {"disableEvent": "DISABLE_EVENT", "enableEvent": "ENABLE_EVENT", "clearEvent": "CLEAR_EVENT"}
# Inlining nests a method's body inside its caller's; code generation recurses over the nesting,
# so the bodies inlined into one another may add at most as many levels as one parsed tree has.
MAX_INLINED_NESTING = MAX_HEIGHT


def statements(stmts: tuple[ast.Stmt, ...] | list[ast.Stmt], ctx: Context, out: list[Item]) -> None:
    for stmt in stmts:
        statement(stmt, ctx, out)


def statement(stmt: ast.Stmt, ctx: Context, out: list[Item]) -> None:
    if isinstance(stmt, ast.Block):
        statements(stmt.statements, ctx, out)
    elif isinstance(stmt, ast.IfStmt):
        _if(stmt, ctx, out)
    elif isinstance(stmt, ast.CallStmt):
        call(stmt.call, ctx, out)
    elif isinstance(stmt, ast.AssignStmt):
        assign(stmt, ctx, out)


def assign(stmt: ast.AssignStmt, ctx: Context, out: list[Item]) -> None:
    state = ctx.state(stmt.name.text)
    if state is None:
        ctx.report(codes.UNSUPPORTED, stmt.name.span, f"'{stmt.name.text}' is not a state here")
        return
    value(stmt.value, ctx, out)
    ctx.need("STORE_STATE", stmt.span, "state needs the extension instruction")
    emit(out, "STORE_STATE", state.index, span=stmt.span)
    if state.travelling and not ctx.in_body and not ctx.watched:  # the program carries it on
        emit(out, "LOAD_STATE", state.index, span=stmt.span)
        emit(out, "STORE_DATA", span=stmt.span)


def _if(stmt: ast.IfStmt, ctx: Context, out: list[Item]) -> None:
    otherwise = Label("else")
    cjump(stmt.condition, otherwise, False, ctx, out)
    statement(stmt.then_body, ctx, out)
    if stmt.else_body is None:
        out.append(otherwise)
        return
    end = Label("endif")
    emit(out, "GOTO", end, span=stmt.span)
    out.append(otherwise)
    statement(stmt.else_body, ctx, out)
    out.append(end)


def body_of(block: ast.Node, ctx: Context, end_op: str) -> Body:
    code: list[Item] = []
    saved, ctx.in_body = ctx.in_body, True
    if isinstance(block, ast.Block):
        statements(block.statements, ctx, code)
    ctx.in_body = saved
    emit(code, end_op, span=getattr(block, "span", None))
    return Body(code)


def call(node: ast.Call, ctx: Context, out: list[Item]) -> None:
    if isinstance(node, ast.GlobalCall):
        role = ctx.table.id_of(node.role.text) or 0
        number = USER_COMMAND_BASE + ctx.command_numbers.get(node.name.text, 0)
        argument = node.args[0] if node.args and not isinstance(node.args[0], ast.Block) else None
        folded = fold(argument, ctx) if argument is not None else None
        if argument is None or folded is not None:
            emit(out, "SEND_COMMAND", role, number, folded.value if folded else 0, span=node.span)
        else:  # an argument known only at run time
            value(argument, ctx, out)
            ctx.ext("SEND_COMMAND_STACK_ARG", node.span)
            emit(out, "SEND_COMMAND_STACK_ARG", role, number, span=node.span)
    elif isinstance(node, ast.SelfCall) and node.name.text not in QUERIES:
        _self_call(node, ctx, out)


def _self_call(node: ast.SelfCall, ctx: Context, out: list[Item]) -> None:
    name, args, span = node.name.text, node.args, node.span
    handler = PRIMITIVE_CODE.get(name)
    if handler is not None:
        handler(args, ctx, out, span)
        return
    method = ctx.method(name)
    if method is None or method.decl.body is None:
        ctx.report(codes.UNSUPPORTED, span, f"'self.{name}' has no body to inline")
    elif name in ctx.inlining:
        ctx.report(codes.UNSUPPORTED, span, f"'self.{name}' calls itself; it cannot be inlined")
    elif ctx.inlined_nesting + nesting(method.decl.body, ctx) > MAX_INLINED_NESTING:
        ctx.report(codes.UNSUPPORTED, span,
                   f"plain method calls nest too deeply to inline ({len(ctx.inlining) + 1} calls "
                   f"deep: {_chain([*ctx.inlining, name])}: more than {MAX_INLINED_NESTING} levels, "
                   "each operator of 'a + b + c' and 'else if' counting); call fewer methods inside "
                   "one another")
    else:
        saved = ctx.inlined_nesting
        saved_bindings = ctx.bindings
        # a parameter stands for its argument, evaluated where it is read (expressions are pure)
        ctx.bindings = {param.text: (arg, saved_bindings)
                        for param, arg in zip(method.decl.params, args, strict=False)}
        ctx.inlined_nesting += nesting(method.decl.body, ctx)
        ctx.inlining.append(name)
        statements(method.decl.body.statements, ctx, out)
        ctx.inlining.pop()
        ctx.inlined_nesting = saved
        ctx.bindings = saved_bindings


def nesting(node: ast.Node, ctx: Context) -> int:
    """Levels of the tree under ``node`` (an upper bound of the recursion it costs), without
    recursion; memoised per compilation."""
    key = ("nesting", id(node))
    if key not in ctx.cache:
        deepest, stack = 0, [(node, 1)]
        while stack:
            current, level = stack.pop()
            deepest = max(deepest, level)
            stack.extend((child, level + 1) for child in ast.children(current))
        ctx.cache[key] = deepest
    return ctx.cache[key]  # type: ignore[return-value]


def _chain(names: list[str]) -> str:
    if len(names) > 12:  # keep the message one readable line
        names = [*names[:6], f"... ({len(names) - 12} more)", *names[-6:]]
    return " -> ".join(names)


def _runtime_value(name: str, arg: ast.Node, ctx: Context, out: list[Item], span: object,
                   instead: str = "") -> bool:
    """A value known only at run time for primitive ``name``: the value, then the Module API's
    stack instruction for it (which checks its range at run time). False, with nothing emitted,
    where the target lacks that instruction; E605 then says why unless ``instead`` names code that
    the caller emits in its place."""
    op = lookup_self(name).runtime_op  # type: ignore[union-attr]
    if op is not None and ctx.has(op):
        value(arg, ctx, out)
        emit(out, op, span=span)
        return True
    table = known_values(arg, ctx)
    allowed = lookup_self(name).values  # type: ignore[union-attr]
    wrong = [result for _, result in table or () if allowed is not None and not (
        allowed[0] <= result <= allowed[1] and result % allowed[2] == 0)]
    if table is not None and wrong:
        ctx.cannot(arg.span, f"self.{name}() would get {wrong[0]} from a value the program sends this "  # type: ignore[arg-type]
                             f"command, outside what it takes; the {ctx.target.name} target has no "
                             f"run-time check ({op} is the default target's)")
        return True
    if table is not None:  # the program sends the command only these values: one constant each
        _table(name, table, ctx, out, span)
        return True
    if not instead:
        ctx.cannot(arg.span, f"self.{name}() with a value known only at run time needs {op}, which the "  # type: ignore[arg-type]
                             f"{ctx.target.name} target does not run: its instruction takes the value as "
                             "an operand, written in the code; use a constant (or branch: if (v == 30) "
                             f"self.{name}(30); else ...)")
    return False


def _table(name: str, table: list[tuple[int, int]], ctx: Context, out: list[Item], span: object) -> None:
    """For a target without the stack instruction: compare the command's argument with each value
    the program sends it (ascending; the last needs no test) and run the primitive with that
    value's constant. ``if (v > k) next; primitive(f(k)); goto end; next: ...``."""
    end = Label("end")
    parameter = ast.NameRef(ast.Name(ctx.argument, span), span)  # type: ignore[arg-type]
    for sent, result in table[:-1]:
        later = Label("next")
        cjump(ast.Binary(">", parameter, literal(sent, span), span, span), later, True, ctx, out)  # type: ignore[arg-type]
        PRIMITIVE_CODE[name]((literal(result, span),), ctx, out, span)
        emit(out, "GOTO", end, span=span)
        out.append(later)
    PRIMITIVE_CODE[name]((literal(table[-1][1], span),), ctx, out, span)
    out.append(end)


def _turn_continuously(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
    if not args:
        return
    if fold(args[0], ctx) is None:
        # the firmware has no TURN_STACK: it branches on the sign and APPLYs ROTATE_CW/CCW
        if not _runtime_value("turnContinuously", args[0], ctx, out, span, instead="branches"):
            _turn_by_value(args[0], ctx, out, span)
        return
    speed = const_arg(args[0], ctx, "the speed")
    if speed is None:
        return
    if speed > 0:
        emit(out, "EVAL_COMMAND", ROTATE_CW, speed, span=span)
    elif speed < 0:
        emit(out, "EVAL_COMMAND", ROTATE_CCW, -speed, span=span)
    else:
        emit(out, "EVAL_COMMAND", STOP, 0, span=span)


def _turn_by_value(speed: ast.Node, ctx: Context, out: list[Item], span: object) -> None:
    """A speed known only at run time: APPLY the direction's command to |speed| (0 stops)."""
    forward, backward = ROTATE_CW, ROTATE_CCW
    inner = ast.unparen(speed)
    if isinstance(inner, ast.Unary) and inner.op == "-" and not ctx.has("NEGATE"):
        speed, forward, backward = inner.operand, ROTATE_CCW, ROTATE_CW  # -e: e, the other way round
    zero = ast.IntLit(0, speed.span)
    backwards, stop, end = Label("ccw"), Label("stop"), Label("end")
    cjump(ast.Binary(">", speed, zero, speed.span, speed.span), backwards, False, ctx, out)
    value(speed, ctx, out)
    emit(out, "PUSH", forward, span=span)
    emit(out, "APPLY", span=span)
    emit(out, "GOTO", end, span=span)
    out.append(backwards)
    if is_nonnegative(speed, ctx):  # never below 0: not positive means stop
        emit(out, "EVAL_COMMAND", STOP, 0, span=span)
        out.append(end)
        return
    cjump(ast.Binary("<", speed, zero, speed.span, speed.span), stop, False, ctx, out)
    value(speed, ctx, out)
    ctx.need("NEGATE", speed.span, "a turning speed below 0 known only at run time needs")
    emit(out, "NEGATE", span=span)
    emit(out, "PUSH", backward, span=span)
    emit(out, "APPLY", span=span)
    emit(out, "GOTO", end, span=span)
    out.append(stop)
    emit(out, "EVAL_COMMAND", STOP, 0, span=span)
    out.append(end)


def _tens(command: int, name: str):  # type: ignore[no-untyped-def]
    def generate(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
        written = ast.signed_literal(args[0]) if args else None
        if written is not None:  # degrees as written, beyond a value's -128..127 (turnTowards(150))
            emit(out, "EVAL_COMMAND", command, int(written / 10), span=span)
            return
        if args and fold(args[0], ctx) is None:
            _runtime_value(name, args[0], ctx, out, span)
            return
        degrees = const_arg(args[0], ctx, "the angle") if args else None
        if degrees is None:
            return
        emit(out, "EVAL_COMMAND", command, int(degrees / 10), span=span)
    return generate


def _immediate(op: str, what: str):  # type: ignore[no-untyped-def]
    def generate(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
        operand = const_arg(args[0], ctx, what) if args else None
        if operand is not None:
            emit(out, op, operand, span=span)
    return generate


def _value_or_stack(op: str, name: str, what: str):  # type: ignore[no-untyped-def]
    """A constant as the immediate operand of ``op``; a value known only at run time (a state,
    an argument) through the Module API's stack instruction for ``name``."""
    immediate = _immediate(op, what)

    def generate(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
        if not args:
            return
        if fold(args[0], ctx) is not None:
            immediate(args, ctx, out, span)
        else:
            _runtime_value(name, args[0], ctx, out, span)
    return generate


def _no_operand(op: str, *operands: int):  # type: ignore[no-untyped-def]
    def generate(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
        emit(out, op, *operands, span=span)
    return generate


def _handle_event(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
    event = const_arg(args[0], ctx, "the event") if args else None
    if event is None or len(args) < 2:
        return
    saved, ctx.mixins = ctx.mixins, list(ctx.mixins)
    body = body_of(args[1], ctx, "END_TERMINATE")
    if ctx.split_handler is not None and isinstance(args[1], ast.Block):  # too large: split (handlers)
        body = ctx.split_handler(args[1], body, ctx)
    ctx.mixins = saved
    _warn_refiring(body, event, ctx, span)
    _warn_missed(event, ctx, span)
    emit(out, "HANDLE_EVENT", event, body, span=span)


SLEEPS = ("sleep", "sleepWhileTurning")


def _warn_missed(event: int, ctx: Context, span: object) -> None:
    """On the firmware a module looks at its sensors only between tasks, and a sleeping behaviour
    blocks it (for a second, or until the joint has turned): an object seen meanwhile is missed."""
    if not ctx.target.quirks.firmware_controller:
        return
    for method in ctx.model.roles[ctx.role].methods.values():
        if method.kind is not ast.MethodKind.BEHAVIOR or method.decl.body is None:
            continue
        nodes = ast.walk(method.decl.body)
        if any(isinstance(node, ast.SelfCall) and node.name.text in SLEEPS for node in nodes):
            ctx.report(codes.HANDLER_MISSED, span,  # type: ignore[arg-type]
                       f"in role {ctx.role}: behaviour {method.name} sleeps, and on the {ctx.target.name} "
                       f"target the module looks at its sensors only between tasks: an object seen by "
                       f"EVENT_PROXIMITY_{event} for less than a sleep is never noticed")
            return


def _warn_refiring(body: Body, event: int, ctx: Context, span: object) -> None:
    """On a target that runs a handler again on every step while its sensor sees an object, a
    handler should first disable (or clear) its own event."""
    if not ctx.target.quirks.handler_refires_with_zero:
        return
    first = next((item for item in body.code if isinstance(item, Ins)), None)
    if first is not None and first.op in ("DISABLE_EVENT", "CLEAR_EVENT") and first.args == (event,):
        return
    ctx.report(codes.HANDLER_REFIRES, span,  # type: ignore[arg-type]
               f"in role {ctx.role}: this handler does not first disable EVENT_PROXIMITY_{event}; on the "
               f"{ctx.target.name} target it runs again on every step while the sensor sees an object; "
               f"begin it with self.disableEvent(EVENT_PROXIMITY_{event}) and enable the event again later")


def _enable_event(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
    event = const_arg(args[0], ctx, "the event") if args else None
    if event is None:
        return
    if ctx.target.quirks.enable_event_toggles:  # ENABLE_EVENT flips the flag: disable it first
        emit(out, "DISABLE_EVENT", event, span=span)
    emit(out, "ENABLE_EVENT", event, span=span)


def _assume_role(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
    mixin_ref = ast.unparen(args[0]) if args else None
    if not isinstance(mixin_ref, ast.NameRef) or len(args) < 2:
        return
    mixin = mixin_ref.name.text
    applied = ctx.table.id_of(application_name(mixin, ctx.role))
    if applied is None:
        ctx.report(codes.UNSUPPORTED, span, f"mixin {mixin} cannot be applied to {ctx.role}")
        return
    restore = ctx.current_role_id()
    emit(out, "SET_ROLE_NOTIFY", applied, span=mixin_ref.span)
    ctx.mixins.append(mixin)
    block = args[1]
    if isinstance(block, ast.Block):
        statements(block.statements, ctx, out)
    ctx.mixins.pop()
    emit(out, "SET_ROLE_NOTIFY", restore, span=span)


PRIMITIVE_CODE = {
    "turnContinuously": _turn_continuously,
    "turnTowards": _tens(ROTATE_TO, "turnTowards"),
    "turnDegrees": _tens(ROTATE_DEGREES, "turnDegrees"),
    "stopTurning": _no_operand("EVAL_COMMAND", STOP, 0),
    "sleepWhileTurning": _value_or_stack("SLEEP_ROTATIONS", "sleepWhileTurning", "the number of turns"),
    "sleep": _no_operand("SLEEP"),
    "setLed": _value_or_stack("SET_LED", "setLed", "the LED value"),
    "handleEvent": _handle_event,
    "assumeRole": _assume_role,
    **{name: _immediate(op, "the event") for name, op in EVENT_OPS.items()},
    "enableEvent": _enable_event,
    **{name: connectors.statement(name) for name in connectors.OPS},
}
