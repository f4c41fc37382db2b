"""Constant folding, a small type inference, and evaluation over a module's local state.

Local state = (axis, connected connset): enough to decide every invariant that uses only
``center_position``, ``total_connected``, ``connected`` and ``sizeof``. Other queries are
"not local" (None).
"""

from __future__ import annotations

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.geometry import facing
from rdcd_core.module_api import FUNCTIONS, SELF_PRIMITIVES
from rdcd_core.operators import BINARY, DIVISIONS, UNARY
from rdcd_core.semantics.model import Value
from rdcd_core.semantics.walk import CALLS
from rdcd_core.syntax import ast
from rdcd_core.types import Type

LOCAL_QUERIES = ("center_position", "total_connected", "connected")


def fold(expr: ast.Node, ctx: Context) -> Value | None:
    """The compile-time value of ``expr`` for ``ctx.role``, or None."""
    kind = type(expr)
    if kind is ast.IntLit:
        return Value(Type.INT, expr.value)
    if kind in CALLS:  # a query has a value only over a local state (``eval_vector``)
        return None
    return _eval(expr, ctx, None)


def type_of(expr: ast.Node, ctx: Context) -> Type:
    expr = ast.unparen(expr)
    if isinstance(expr, ast.IntLit):
        return Type.INT
    if isinstance(expr, ast.NameRef):
        value = ctx.constant(expr.name.text)
        return value.type if value is not None else Type.INT
    if isinstance(expr, ast.Unary):
        return Type.BOOL if expr.op == "!" else Type.INT
    if isinstance(expr, ast.Binary):
        return BINARY[expr.op].result
    if isinstance(expr, (ast.SelfCall, ast.FunctionCall)):  # a plain method gives nothing to fold
        table = SELF_PRIMITIVES if isinstance(expr, ast.SelfCall) else FUNCTIONS
        primitive = table.get(expr.name.text)
        return primitive.result if primitive else Type.VOID
    return Type.VOID


def _eval(expr: ast.Node, ctx: Context, state: tuple[int, int] | None) -> Value | None:
    expr = ast.unparen(expr)
    if isinstance(expr, ast.IntLit):
        return Value(Type.INT, expr.value)
    if isinstance(expr, ast.NameRef):
        bound = ctx.bindings.get(expr.name.text)
        if bound is not None:  # a plain method's parameter: its argument, in the caller's bindings
            saved, ctx.bindings = ctx.bindings, bound[1]  # type: ignore[assignment]
            try:
                return _eval(bound[0], ctx, state)  # type: ignore[arg-type]
            finally:
                ctx.bindings = saved
        return ctx.constant(expr.name.text)
    if isinstance(expr, ast.Unary):
        inner = _eval(expr.operand, ctx, state)
        if inner is None:
            return None
        operator = UNARY[expr.op]
        return Value(operator.operand, operator.apply(inner.value))
    if isinstance(expr, ast.Binary):
        return _eval_binary(expr, ctx, state)
    if state is not None and isinstance(expr, (ast.SelfCall, ast.FunctionCall)):
        return _eval_query(expr, ctx, state)
    return None


def _eval_binary(expr: ast.Binary, ctx: Context, state: tuple[int, int] | None) -> Value | None:
    left = _eval(expr.left, ctx, state)
    operator = BINARY[expr.op]
    if operator.decides is not None and left is not None:
        if bool(left.value) == operator.decides:
            return Value(Type.BOOL, int(operator.decides))
        right = _eval(expr.right, ctx, state)
        return None if right is None else Value(Type.BOOL, int(bool(right.value)))
    right = _eval(expr.right, ctx, state)
    if left is None or right is None or (expr.op in DIVISIONS and right.value == 0):
        return None  # a zero divisor is never folded: E212, or the VM's runtime error
    return Value(operator.result, operator.apply(left.value, right.value))


def _eval_query(expr: ast.Node, ctx: Context, state: tuple[int, int]) -> Value | None:
    axis, connected = state
    name = expr.name.text
    if isinstance(expr, ast.FunctionCall):
        if name != "sizeof" or len(expr.args) != 1:
            return None
        inner = _eval(expr.args[0], ctx, state)
        return None if inner is None else Value(Type.INT, bin(inner.value & 0xFF).count("1"))
    if name == "center_position":
        return Value(Type.AXIS, axis)
    if name == "total_connected":
        return Value(Type.CONNSET, connected)
    if name == "connected" and len(expr.args) == 1:
        direction = fold(expr.args[0], ctx)
        if direction is None:
            return None
        return Value(Type.CONNSET, connected & facing(axis, direction.value))
    return None


def eval_vector(expr: ast.Node, ctx: Context, states: tuple[tuple[int, int], ...]) -> list[int] | None:
    """The value of ``expr`` in every local state (None if it is not local).

    Memoised per ``local_shape``: the invariants of a large role repeat a few shapes, and each new
    vector costs a pass over every state.
    """
    shape = local_shape(expr, ctx)
    return None if shape is None else vector_of(shape, ctx, states)


def local_shape(expr: ast.Node, ctx: Context) -> tuple | None:
    """What ``expr`` computes from the local state, its constants folded for ``ctx.role``: two
    expressions with equal shapes have equal values in every local state. None if not local."""
    key = ("shape", id(expr))
    if key not in ctx.cache:
        ctx.cache[key] = _shape(ast.unparen(expr), ctx)
    return ctx.cache[key]  # type: ignore[return-value]


def _shape(expr: ast.Node, ctx: Context) -> tuple | None:
    folded = fold(expr, ctx)
    if folded is not None:
        return ("const", folded.value)
    parts: tuple = ()
    if isinstance(expr, ast.Unary):
        parts = ("unary", expr.op, local_shape(expr.operand, ctx))
    elif isinstance(expr, ast.Binary) and (expr.op not in DIVISIONS or _nonzero(expr.right, ctx)):
        # a divisor that is not a constant may be 0 in some state: a runtime error, not a value
        parts = ("binary", expr.op, local_shape(expr.left, ctx), local_shape(expr.right, ctx))
    elif isinstance(expr, ast.FunctionCall) and expr.name.text == "sizeof" and len(expr.args) == 1:
        parts = ("sizeof", local_shape(expr.args[0], ctx))
    elif isinstance(expr, ast.SelfCall) and expr.name.text in ("center_position", "total_connected"):
        parts = ("query", expr.name.text)
    elif isinstance(expr, ast.SelfCall) and expr.name.text == "connected" and len(expr.args) == 1:
        direction = fold(expr.args[0], ctx)
        parts = ("query", "connected", direction.value if direction is not None else None)
    if not parts or None in parts:  # not local, or a part is not
        return None
    return parts


def _nonzero(expr: ast.Node, ctx: Context) -> bool:
    folded = fold(expr, ctx)
    return folded is not None and folded.value != 0


def vector_of(shape: tuple, ctx: Context, states: tuple[tuple[int, int], ...]) -> list[int]:
    """The value of a local shape in each of ``states``, memoised per compilation."""
    key = ("vector", shape, id(states))
    if key not in ctx.cache:
        ctx.cache[key] = _vector(shape, ctx, states)
    return ctx.cache[key]  # type: ignore[return-value]


def _vector(shape: tuple, ctx: Context, states: tuple[tuple[int, int], ...]) -> list[int]:
    kind = shape[0]
    if kind == "const":
        return [shape[1]] * len(states)
    if kind == "query":
        if shape[1] == "center_position":
            return [axis for axis, _ in states]
        if shape[1] == "total_connected":
            return [connected for _, connected in states]
        return [connected & facing(axis, shape[2]) for axis, connected in states]
    if kind == "sizeof":
        return [bin(v & 0xFF).count("1") for v in vector_of(shape[1], ctx, states)]
    if kind == "unary":
        return list(map(UNARY[shape[1]].apply, vector_of(shape[2], ctx, states)))
    left, right = vector_of(shape[2], ctx, states), vector_of(shape[3], ctx, states)
    return list(map(BINARY[shape[1]].apply, left, right))
