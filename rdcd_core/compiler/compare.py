"""Conditional jumps on comparisons: the cheapest original-ISA form of each comparison."""

from __future__ import annotations

from rdcd_core.compiler import lowering
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.fold import fold, type_of
from rdcd_core.compiler.ir import Item, Label
from rdcd_core.syntax import ast
from rdcd_core.types import Type


def is_nonnegative(expr: ast.Node, ctx: Context) -> bool:
    expr = ast.unparen(expr)
    return type_of(expr, ctx) is Type.CONNSET or (
        isinstance(expr, ast.FunctionCall) and expr.name.text == "sizeof")


def _reads_state(expr: ast.Node, ctx: Context) -> bool:
    return any(isinstance(node, ast.NeighbourValues)
               or (isinstance(node, ast.NameRef) and ctx.state(node.name.text) is not None)
               for node in ast.walk(expr))


def _equals(left: ast.Node, right: ast.Node, target: Label, when: bool, ctx: Context,
            out: list[Item], span: object) -> None:
    """a == b with the EQUALS extension: each side read once."""
    from rdcd_core.compiler import exprgen as g

    g.value(left, ctx, out)
    g.value(right, ctx, out)
    g.emit(out, "EQUALS", span=span)
    g.jump_on(when, target, out, span)


def cjump_compare(expr: ast.Binary, target: Label, when: bool, ctx: Context, out: list[Item]) -> None:
    from rdcd_core.compiler import exprgen as g

    left, right, op = expr.left, expr.right, expr.op
    if fold(left, ctx) is not None and fold(right, ctx) is None:
        left, right, op = right, left, g.MIRROR[op]
    constant = fold(right, ctx)
    if constant is not None:
        left, right, op = _move_constant(left, right, op, constant.value, ctx)
        constant = fold(right, ctx)
    span = expr.span
    direction = lowering.connected_direction(left, ctx)
    if (constant is not None and direction is not None
            and ctx.target.quirks.connected_dir_sizeof_popcount_of_count):
        lowering.dir_count_jump(direction, op, constant.value, target, when, ctx, out, span)
        return
    if op in ("==", "!=") and type_of(left, ctx) is Type.BOOL:
        _bool_equality(left, right, target, when == (op == "=="), ctx, out)
        return
    state_equality = op in ("==", "!=") and ctx.has("EQUALS") and _reads_state(expr, ctx)
    if state_equality and constant is None:  # a value read from state: EQUALS, not two reads
        _equals(left, right, target, when == (op == "=="), ctx, out, span)
        return
    if constant is not None:
        k = constant.value
        if op in ("==", "!=") and g.query_name(left) == "center_position" and k in g.AXIS_OPS:
            g.emit(out, g.AXIS_OPS[k], span=span)
            g.jump_on(when == (op == "=="), target, out, span)
            return
        nonneg = is_nonnegative(left, ctx)
        readable = _readable(left, ctx)  # else only the fused comparisons below read it
        if not readable:
            pass
        elif (op == "!=" and k == 0) or (nonneg and (op, k) in ((">", 0), (">=", 1))):
            g.truth(left, ctx, out)
            g.jump_on(when, target, out, span)
            return
        if readable and ((op == "==" and k == 0) or (nonneg and (op, k) in (("<=", 0), ("<", 1)))):
            g.truth(left, ctx, out)
            g.jump_on(not when, target, out, span)
            return
        if readable and op in ("==", "!=") and 1 <= k <= 4 and ctx.has(f"EQUALS_{k}"):
            g.value(left, ctx, out)
            g.emit(out, f"EQUALS_{k}", span=span)
            g.jump_on(when == (op == "=="), target, out, span)
            return
        if state_equality:  # a state and any other constant: one EQUALS, one read
            _equals(left, right, target, when == (op == "=="), ctx, out, span)
            return
        if op == ">=" and k > -128:
            op, right, k = ">", _literal(k - 1, right), k - 1
        elif op == "<=" and k < 127:
            op, right, k = "<", _literal(k + 1, right), k + 1
        if op == ">" and k == -1:  # x > -1 is x >= 0: a one-byte constant
            op, right = ">=", _literal(0, right)
    if op in ("==", "!="):
        _equality(left, right, target, when == (op == "=="), ctx, out, span)
    elif op in ("<=", ">="):
        g.compare(left, right, ">" if op == "<=" else "<", ctx, out, span)
        g.jump_on(not when, target, out, span)
    else:
        g.compare(left, right, op, ctx, out, span)
        g.jump_on(when, target, out, span)


def _readable(expr: ast.Node, ctx: Context) -> bool:
    """Whether the target can push the value of ``expr`` when it is a coordinate query (the
    original firmware only compares x and y with a value)."""
    from rdcd_core.compiler import exprgen as g

    inner = ast.unparen(expr)
    name = g.query_name(inner)
    return not (isinstance(inner, ast.SelfCall) and name in g.COORDS) or ctx.has(f"COORD_{g.COORDS[name]}")


def _move_constant(left: ast.Node, right: ast.Node, op: str, k: int, ctx: Context) -> tuple:
    """(a + c) op k  ->  a op (k - c), and the like, so that no ADD/SUB extension is needed.
    (Differs from 8-bit wrapping arithmetic only where a + c overflows.)"""
    from rdcd_core.compiler import exprgen as g

    inner = ast.unparen(left)
    if isinstance(inner, ast.Unary) and inner.op == "-" and not ctx.has("NEGATE") and -k <= 127:
        # -a op k  <=>  a mirror(op) -k, where the target cannot negate
        return _move_constant(inner.operand, _literal(-k, right), g.MIRROR[op], -k, ctx)
    if not isinstance(inner, ast.Binary) or inner.op not in "+-":
        return left, right, op
    a, c = fold(inner.left, ctx), fold(inner.right, ctx)
    if c is not None and a is None:
        value = k - c.value if inner.op == "+" else k + c.value
        result = (inner.left, value, op)
    elif a is not None and c is None:
        if inner.op == "+":
            result = (inner.right, k - a.value, op)
        else:  # c - x op k  <=>  x mirror(op) c - k
            result = (inner.right, a.value - k, g.MIRROR[op])
    else:
        return left, right, op
    operand, value, new_op = result
    if not -128 <= value <= 127:
        return left, right, op
    operand, new_right, new_op = _move_constant(operand, _literal(value, right), new_op, value, ctx)
    return operand, new_right, new_op


def _literal(value: int, like: ast.Node) -> ast.Node:
    if value >= 0:
        return ast.IntLit(value, like.span)
    return ast.Unary("-", ast.IntLit(-value, like.span), like.span)


def _equality(left: ast.Node, right: ast.Node, target: Label, when: bool, ctx: Context,
              out: list[Item], span: object) -> None:
    """a == b as !(a > b) && !(a < b)."""
    from rdcd_core.compiler import exprgen as g

    if when:
        skip = Label("ne")
        g.compare(left, right, ">", ctx, out, span)
        g.jump_on(True, skip, out, span)
        g.compare(left, right, "<", ctx, out, span)
        g.jump_on(False, target, out, span)
        out.append(skip)
    else:
        for op in (">", "<"):
            g.compare(left, right, op, ctx, out, span)
            g.jump_on(True, target, out, span)


def _bool_equality(left: ast.Node, right: ast.Node, target: Label, when: bool, ctx: Context,
                   out: list[Item]) -> None:
    from rdcd_core.compiler import exprgen as g

    left_false, end = Label("lf"), Label("end")
    g.cjump(left, left_false, False, ctx, out)
    g.cjump(right, target, when, ctx, out)
    g.emit(out, "GOTO", end)
    out.append(left_false)
    g.cjump(right, target, not when, ctx, out)
    out.append(end)
