"""Code for expressions: ``value`` pushes a value; ``cjump`` jumps to a label when a condition has
a given truth value and falls through otherwise. Every query is pure, so an operand may be
evaluated twice; that is how ``==`` is compiled without the EQUALS extension."""

from __future__ import annotations

from rdcd_core.compiler import codes, connectors
from rdcd_core.compiler.compare import cjump_compare
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.fold import fold, type_of
from rdcd_core.compiler.geometry import DIRECTION_NAMES, ROLE_DIRECTION_OPS
from rdcd_core.compiler.ir import Body, Ins, Item, Label
from rdcd_core.syntax import ast
from rdcd_core.types import PREDEFINED_VALUES, Type
from vm.isa.opcodes import AGGREGATES, WHERE_ALL, WHERE_CHILDREN, WHERE_CONNECTOR

COORDS = {"x": "X", "y": "Y", "z": "Z"}
AXIS_OPS = {PREDEFINED_VALUES[name].code: f"CENTER_POSITION_{short}"  # axis code -> its test
            for name, short in (("EAST_WEST", "EW"), ("NORTH_SOUTH", "NS"), ("UP_DOWN", "UD"))}
ARITHMETIC = {"+": "ADD", "-": "SUB", "*": "MUL", "/": "DIV", "%": "MOD"}  # saturating, vm.isa.opcodes
MIRROR = {"<": ">", ">": "<", "<=": ">=", ">=": "<=", "==": "==", "!=": "!="}


def emit(out: list[Item], op: str, *args: object, span: object = None) -> None:
    out.append(Ins(op, tuple(args), span))


def query_name(expr: ast.Node) -> str | None:
    expr = ast.unparen(expr)
    if isinstance(expr, (ast.SelfCall, ast.FunctionCall)):
        return expr.name.text
    return None


def const_arg(expr: ast.Node, ctx: Context, what: str) -> int | None:
    value = fold(expr, ctx)
    if value is None:
        ctx.report(codes.NOT_CONSTANT, expr.span, f"{what} must be a compile-time constant on the DCD-VM")
        return None
    return value.value


def value(expr: ast.Node, ctx: Context, out: list[Item]) -> None:
    expr = ast.unparen(expr)
    folded = fold(expr, ctx)
    if folded is not None:
        emit(out, "PUSH", folded.value, span=expr.span)
    elif isinstance(expr, ast.SelfCall):
        _query(expr, ctx, out)
    elif isinstance(expr, ast.FunctionCall):
        _function(expr, ctx, out)
    elif isinstance(expr, ast.Unary) and expr.op == "-":
        value(expr.operand, ctx, out)
        ctx.need("NEGATE", expr.span, "the value of a negated expression needs")
        emit(out, "NEGATE", span=expr.span)
    elif isinstance(expr, ast.Binary) and _by_one(expr, ctx, out):
        pass
    elif isinstance(expr, ast.Binary) and expr.op in ARITHMETIC:
        value(expr.left, ctx, out)
        value(expr.right, ctx, out)
        op = ARITHMETIC[expr.op]
        ctx.ext(op, expr.span)
        emit(out, op, span=expr.span)
    elif isinstance(expr, ast.Binary) and expr.op in ("<", ">"):
        compare(expr.left, expr.right, expr.op, ctx, out, expr.span)
    elif isinstance(expr, ast.NameRef) and _name_value(expr, ctx, out):
        pass
    else:
        materialize(expr, ctx, out)


def _by_one(expr: ast.Binary, ctx: Context, out: list[Item]) -> bool:
    """``e * 1``, ``1 * e``, ``e / 1``: e; with -1: ``-e`` (NEGATE saturates as MUL and DIV do:
    -128 gives 127). ``speed * side`` with a role's constant side costs nothing beyond ``speed``."""
    operands = [(expr.left, expr.right)] + ([(expr.right, expr.left)] if expr.op == "*" else [])
    if expr.op not in ("*", "/"):
        return False
    for operand, factor in operands:
        folded = fold(factor, ctx)
        if folded is None or folded.value not in (1, -1) or (folded.value < 0 and not ctx.has("NEGATE")):
            continue
        value(operand, ctx, out)
        if folded.value < 0:
            emit(out, "NEGATE", span=expr.span)
        return True
    return False


def _name_value(expr: ast.NameRef, ctx: Context, out: list[Item]) -> bool:
    """A state (LOAD_STATE), the command's parameter (PUSH_ARGUMENT) or a plain method's
    argument (its expression, in its caller's bindings); False for any other name."""
    name = expr.name.text
    bound = ctx.bindings.get(name)
    if bound is not None:
        arg, outer = bound
        saved, ctx.bindings = ctx.bindings, outer  # type: ignore[assignment]
        try:
            value(arg, ctx, out)  # type: ignore[arg-type]
        finally:
            ctx.bindings = saved
        return True
    if name == ctx.argument:
        emit(out, "PUSH_ARGUMENT", 0, span=expr.span)
        return True
    state = ctx.state(name)
    if state is None:
        return False
    ctx.need("LOAD_STATE", expr.span, "state needs the extension instruction")
    emit(out, "LOAD_STATE", state.index, span=expr.span)
    return True


def neighbour_values(call: ast.FunctionCall, ctx: Context, out: list[Item]) -> bool:
    """``min(neighbours.s)``, ``count(children.s)``, …: NBR_AGG; False if not that form."""
    if len(call.args) != 1 or not isinstance(ast.unparen(call.args[0]), ast.NeighbourValues):
        return False
    values: ast.NeighbourValues = ast.unparen(call.args[0])  # type: ignore[assignment]
    state = ctx.model.states.get(values.name.text)
    kind = AGGREGATES.index(call.name.text) if call.name.text in AGGREGATES else 0
    where = WHERE_CHILDREN if values.children else WHERE_ALL
    if values.where is not None:
        folded = fold(values.where, ctx)
        if folded is not None:
            where = folded.value if type_of(values.where, ctx) is Type.DIR else WHERE_CONNECTOR + folded.value
    ctx.need("NBR_AGG", call.span, "the neighbours' values need the extension instruction")
    emit(out, "NBR_AGG", (kind << 4) | (state.index & 7 if state else 0), where, span=call.span)
    return True


def materialize(expr: ast.Node, ctx: Context, out: list[Item]) -> None:
    """A boolean (or an axis) as 0/1 (or its code) through branches."""
    end = Label("end")
    if type_of(expr, ctx) is Type.AXIS:
        *tested, last = AXIS_OPS  # the last axis is what is left when the others fail
        for axis in tested:
            skip = Label()
            emit(out, AXIS_OPS[axis], span=expr.span)
            emit(out, "IF_FALSE_GOTO", skip, span=expr.span)
            emit(out, "PUSH", axis, span=expr.span)
            emit(out, "GOTO", end, span=expr.span)
            out.append(skip)
        emit(out, "PUSH", last, span=expr.span)
    else:
        false = Label("false")
        cjump(expr, false, False, ctx, out)
        emit(out, "PUSH", 1, span=expr.span)
        emit(out, "GOTO", end, span=expr.span)
        out.append(false)
        emit(out, "PUSH", 0, span=expr.span)
    out.append(end)


def _query(expr: ast.SelfCall, ctx: Context, out: list[Item]) -> None:
    name = expr.name.text
    if name in COORDS:
        op = f"COORD_{COORDS[name]}"
        if not ctx.has(op):  # the original firmware only compares x and y with a value
            ctx.cannot(expr.span, f"the value of self.{name}() needs {op}, which the {ctx.target.name} "
                                  "target does not run; compare it with a value instead"
                                  + (" (x and y only)" if name == "z" else ""))
        emit(out, op, span=expr.span)
    elif name == "total_connected":
        if ctx.target.quirks.connected_physical_bits:
            ctx.cannot(expr.span, f"the connector set self.total_connected() is read wrongly by the "
                                  f"{ctx.target.name} target's CONNECTED (physical connectors, connector 7 "
                                  "lost); use sizeof(self.total_connected()) or compare it with 0")
        emit(out, "CONNECTED", span=expr.span)
    elif name == "connected" and expr.args:
        direction = const_arg(expr.args[0], ctx, "the direction")
        ctx.need("CONNECTED_DIR", expr.span, "the connector set self.connected(d) needs")
        emit(out, "CONNECTED_DIR", direction or 0, span=expr.span)
    elif name == "center_position":
        materialize(expr, ctx, out)
    elif name in connectors.OPS:
        connectors.push(name, expr.args, ctx, out, expr.span)
    else:
        ctx.report(codes.UNSUPPORTED, expr.span, f"'self.{name}' has no value on the DCD-VM")
        emit(out, "PUSH", 0, span=expr.span)


def _function(expr: ast.FunctionCall, ctx: Context, out: list[Item]) -> None:
    if expr.name.text == "sizeof" and expr.args:
        inner = ast.unparen(expr.args[0])
        name = query_name(inner)
        if isinstance(inner, ast.SelfCall) and name == "total_connected":
            emit(out, "CONNECTED_SIZEOF", span=expr.span)
        elif isinstance(inner, ast.SelfCall) and name == "connected" and inner.args:
            direction = const_arg(inner.args[0], ctx, "the direction")
            _dir_count_value(direction or 0, ctx, expr.span)
            emit(out, "CONNECTED_DIR_SIZEOF", direction or 0, span=expr.span)
        else:
            value(inner, ctx, out)
            emit(out, "SIZEOF", span=expr.span)
    elif neighbour_values(expr, ctx, out):
        pass
    elif expr.name.text in ("min", "max") and len(expr.args) == 2:
        value(expr.args[0], ctx, out)
        value(expr.args[1], ctx, out)
        op = expr.name.text.upper()
        ctx.ext(op, expr.span)
        emit(out, op, span=expr.span)
    elif expr.name.text == "table" and len(expr.args) >= 2:
        # the values after the fragment's code, one byte each (vm.isa.opcodes TABLE)
        value(expr.args[0], ctx, out)
        entries = [const_arg(arg, ctx, "a value of 'table'") or 0 for arg in expr.args[1:]]
        ctx.ext("TABLE", expr.span)
        emit(out, "TABLE", Body([Ins("PUSH", (v & 0x7F,), expr.span) for v in entries]),
             span=expr.span)
    elif expr.name.text == "connected_role" and len(expr.args) == 2:
        direction = const_arg(expr.args[0], ctx, "the direction")
        role = const_arg(expr.args[1], ctx, "the role")
        ctx.need("CONNECTED_ROLE", expr.span, "the connector set connected_role(d, R) needs")
        emit(out, "CONNECTED_ROLE", direction or 0, role or 0, span=expr.span)
    else:
        ctx.report(codes.UNSUPPORTED, expr.span, f"'{expr.name.text}' cannot be compiled")
        emit(out, "PUSH", 0, span=expr.span)


def compare(left: ast.Node, right: ast.Node, op: str, ctx: Context, out: list[Item], span: object) -> None:
    """Push b(left op right) for op in < >, using COORD_*_GREATER/LESSER where it fits."""
    lname, rname = query_name(left), query_name(right)
    suffix = {">": "GREATER", "<": "LESSER"}
    if lname in COORDS and isinstance(ast.unparen(left), ast.SelfCall):
        value(right, ctx, out)
        _coord_compare(f"COORD_{COORDS[lname]}_{suffix[op]}", lname, ctx, out, span)
    elif rname in COORDS and isinstance(ast.unparen(right), ast.SelfCall):
        value(left, ctx, out)
        _coord_compare(f"COORD_{COORDS[rname]}_{suffix[MIRROR[op]]}", rname, ctx, out, span)
    elif op == "<" and not ctx.has("LESSER"):  # a < b as b > a: every operand is pure
        value(right, ctx, out)
        value(left, ctx, out)
        emit(out, "GREATER", span=span)
    else:
        value(left, ctx, out)
        value(right, ctx, out)
        emit(out, suffix[op], span=span)


def _coord_compare(op: str, name: str, ctx: Context, out: list[Item], span: object) -> None:
    if not ctx.has(op):
        ctx.cannot(span, f"comparing self.{name}() needs {op}, which the {ctx.target.name} target does "  # type: ignore[arg-type]
                         "not run; it has no instruction that reads the z coordinate")
    emit(out, op, span=span)


def _dir_count_value(direction: int, ctx: Context, span: object) -> None:
    """sizeof(self.connected(d)) as a number: exact only where the target counts right."""
    from rdcd_core.compiler import lowering

    if lowering.dir_sizeof_runs(ctx, direction, span) and not lowering.dir_count_is_exact(ctx, direction):  # type: ignore[arg-type]
        ctx.cannot(span, f"the number sizeof(self.connected({DIRECTION_NAMES.get(direction, direction)})) "  # type: ignore[arg-type]
                         f"is read wrongly by the {ctx.target.name} target (2 and 4 connections count as 1); "
                         "compare it with a constant instead")


def jump_on(when: bool, target: Label, out: list[Item], span: object) -> None:
    emit(out, "IF_TRUE_GOTO" if when else "IF_FALSE_GOTO", target, span=span)


def truth(expr: ast.Node, ctx: Context, out: list[Item]) -> None:
    """Push a value that is non-zero exactly when ``expr != 0``."""
    expr = ast.unparen(expr)
    if isinstance(expr, ast.FunctionCall) and expr.name.text == "sizeof" and expr.args:
        truth(expr.args[0], ctx, out)  # a set's size is non-zero exactly when the set is not empty
        return
    if isinstance(expr, ast.FunctionCall) and expr.name.text == "connected_role" and len(expr.args) == 2:
        direction = fold(expr.args[0], ctx)
        role = fold(expr.args[1], ctx)
        if direction is not None and role is not None and direction.value in ROLE_DIRECTION_OPS:
            op = ROLE_DIRECTION_OPS[direction.value]
            if not ctx.has(op):
                ctx.cannot(expr.span, f"connected_role({DIRECTION_NAMES[direction.value]}, ...) needs {op}, "
                                      f"which the {ctx.target.name} target does not run; it tests neighbour "
                                      "roles only below (connected_role(DOWN, ...))")
            emit(out, op, role.value, span=expr.span)
            return
    if isinstance(expr, ast.SelfCall) and expr.name.text == "total_connected":
        emit(out, "CONNECTED_SIZEOF", span=expr.span)  # non-zero exactly when the set is not empty
        return
    if isinstance(expr, ast.SelfCall) and expr.name.text == "connected" and expr.args:
        from rdcd_core.compiler import lowering

        direction = const_arg(expr.args[0], ctx, "the direction")
        lowering.dir_sizeof_runs(ctx, direction or 0, expr.span)
        emit(out, "CONNECTED_DIR_SIZEOF", direction or 0, span=expr.span)  # its reading is 0 only for 0
        return
    value(expr, ctx, out)


def cjump(expr: ast.Node, target: Label, when: bool, ctx: Context, out: list[Item]) -> None:
    expr = ast.unparen(expr)
    folded = fold(expr, ctx)
    if folded is not None:
        if bool(folded.value) == when:
            emit(out, "GOTO", target, span=expr.span)
        return
    if isinstance(expr, ast.Unary) and expr.op == "!":
        cjump(expr.operand, target, not when, ctx, out)
    elif isinstance(expr, ast.Binary) and expr.op in ("&&", "||"):
        if (expr.op == "&&") != when:
            cjump(expr.left, target, when, ctx, out)
            cjump(expr.right, target, when, ctx, out)
        else:
            skip = Label("skip")
            cjump(expr.left, skip, not when, ctx, out)
            cjump(expr.right, target, when, ctx, out)
            out.append(skip)
    elif isinstance(expr, ast.Binary) and expr.op in MIRROR:
        cjump_compare(expr, target, when, ctx, out)
    else:
        truth(expr, ctx, out)
        jump_on(when, target, out, expr.span)
