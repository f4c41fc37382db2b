"""Types and constant folding of expressions (docs/language.md)."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.operators import BINARY, DIVISIONS, UNARY
from rdcd_core.semantics import calls, codes, states
from rdcd_core.semantics.context import did_you_mean
from rdcd_core.semantics.env import Env
from rdcd_core.semantics.model import ConstantSymbol, Value
from rdcd_core.semantics.walk import expr_nodes
from rdcd_core.syntax import ast
from rdcd_core.types import INT8_MAX, INT8_MIN, PREDEFINED_VALUES, Type

Result = tuple[Type | None, Value | None]  # None type: unknown (an error was already reported)

_COMPARABLE = {Type.INT, Type.BOOL, Type.CONNSET, Type.AXIS, Type.DIR, Type.EVENT}


def check_expr(env: Env, expr: ast.Expr) -> Result:
    if isinstance(expr, ast.IntLit):
        return _int_literal(env, expr, negated=False)
    if isinstance(expr, ast.NameRef):
        return _name(env, expr)
    if isinstance(expr, ast.Paren):
        return check_expr(env, expr.expr)
    if isinstance(expr, ast.Unary):
        return _unary(env, expr)
    if isinstance(expr, ast.Binary):
        return _binary(env, expr)
    if isinstance(expr, ast.SelfCall | ast.FunctionCall | ast.GlobalCall):
        result = calls.check_call(env, expr)
        if result[0] is Type.VOID:
            env.ctx.report(codes.VOID_VALUE, expr.span,
                           f"'{expr.name.text}' has no value; it can only be used as a statement")
            return None, None
        return result
    if isinstance(expr, ast.NeighbourValues):
        states.check_values(env, expr)
        env.ctx.report(codes.VALUES_OUT_OF_PLACE, expr.span,
                       f"'{expr.name.text}' of the neighbours is several values: reduce them to one with "
                       f"min(…), max(…), count(…) or sum(…)")
        return None, None
    if isinstance(expr, ast.Block):
        env.ctx.report(codes.BLOCK_NOT_ALLOWED, expr.span,
                       "a block is allowed only as the second argument of handleEvent or assumeRole")
    return None, None


def check_bool(env: Env, expr: ast.Expr, what: str) -> None:
    type_, _ = check_expr(env, expr)
    if type_ is not None and type_ is not Type.BOOL:
        env.ctx.report(codes.NOT_BOOL, expr.span,
                       f"{what} must be a bool, not {type_.value}; compare it, e.g. '... > 0'")


def _int_literal(env: Env, expr: ast.IntLit, negated: bool) -> Result:
    value = -expr.value if negated else expr.value
    if not INT8_MIN <= value <= INT8_MAX:
        digits = len(str(expr.value)) if expr.value < 10**18 else expr.span.end - expr.span.start
        shown = f"integer {value}" if digits <= 20 else \
            f"{'a negative' if negated else 'an'} integer of {digits} digits"
        env.ctx.report(codes.INT_RANGE, expr.span,
                       f"{shown} is outside -128..127; every value is an 8-bit signed integer")
        return Type.INT, None
    return Type.INT, Value(Type.INT, value)


def _name(env: Env, expr: ast.NameRef) -> Result:
    name = expr.name.text
    state = states.read(env, expr)
    if state is not None:
        return state
    symbol, depth = env.lookup_constant(name)
    if symbol is not None:
        env.ctx.reference(expr.name, "constant", env.home_target(name, "constant"))
        if symbol.definition is None or id(symbol) in env.ctx.folded:
            return symbol.type, symbol.value
        return constant_value(env.holder(depth, name), symbol, expr.name)
    predefined = PREDEFINED_VALUES.get(name)
    if predefined is not None:
        env.ctx.reference(expr.name, "predefined", name)
        return predefined.type, Value(predefined.type, predefined.code)
    if name in env.ctx.model.roles:
        env.ctx.reference(expr.name, "role", name)
        env.ctx.report(codes.TYPE_MISMATCH, expr.span,
                       f"role '{name}' is not a value; roles can only be arguments of "
                       "connected_role and assumeRole")
        return None, None
    if not name:
        return None, None
    suffix, fixes = did_you_mean(name, [*env.constant_names(), *env.role.states, *env.ctx.model.states,
                                        *PREDEFINED_VALUES], expr.name.span)
    hint = suffix or f"; declare it as a constant of '{env.home.name}'"
    env.ctx.report(codes.UNKNOWN_NAME, expr.name.span,
                   f"unknown name '{name}'{_unknown_where(env, name)}{hint}", fixes=fixes)
    return None, None


def _unknown_where(env: Env, name: str) -> str:
    """Names the role when ``name`` is a constant of other roles, just not of this one."""
    if env.role is env.home or not any(name in r.constants for r in env.ctx.model.roles.values()):
        return ""
    return f" in role '{env.role.name}'"


def constant_value(holder: Env, symbol: ConstantSymbol, use: ast.Name | None) -> Result:
    """Type and folded value of ``symbol``, folding its definition on first use."""
    ctx = holder.ctx
    key = id(symbol)
    if symbol.definition is None or key in ctx.folded:
        return symbol.type, symbol.value
    if key in ctx.folding:
        if use is not None:
            ctx.report(codes.CONSTANT_CYCLE, use.span,
                       f"constant '{symbol.name}' is defined in terms of itself; give it a value "
                       "that does not refer back to it")
        return None, None
    ctx.folding.add(key)
    type_, value = check_expr(holder, symbol.definition.value)
    ctx.folding.discard(key)
    ctx.folded.add(key)
    symbol.type, symbol.value = type_, value
    return type_, value


def _unary(env: Env, expr: ast.Unary) -> Result:
    operand = ast.unparen(expr.operand)
    if expr.op == "-" and isinstance(operand, ast.IntLit) and expr.operand is operand:
        return _int_literal(env, operand, negated=True)
    type_, value = check_expr(env, expr.operand)
    wanted = UNARY[expr.op].operand
    if type_ is None:
        return wanted, None
    if type_ is not wanted:
        env.ctx.report(codes.TYPE_MISMATCH, expr.span,
                       f"'{expr.op}' needs {a_type(wanted)}, not {a_type(type_)}")
        return wanted, None
    if value is None:
        return wanted, None
    result = UNARY[expr.op].exact(value.value)
    if wanted is Type.BOOL:
        return Type.BOOL, Value(Type.BOOL, result)
    return _ranged(env, expr, result)


def _ranged(env: Env, expr: ast.Expr, value: int) -> Result:
    if not INT8_MIN <= value <= INT8_MAX:
        env.ctx.report(codes.INT_RANGE, expr.span,
                       f"this expression is {value}{where(env, expr)}, outside -128..127; "
                       "every value is an 8-bit signed integer")
        return Type.INT, None
    return Type.INT, Value(Type.INT, value)


def where(env: Env, expr: ast.Arg) -> str:
    """" in role 'R'" when the value of ``expr`` depends on the concrete role it is checked in."""
    if env.role is env.home or isinstance(expr, ast.Block):
        return ""
    for node in expr_nodes(expr):
        if isinstance(node, ast.NameRef) and env.lookup_constant(node.name.text)[0] is not None:
            return f" in role '{env.role.name}'"
    return ""


def a_type(type_: Type | None) -> str:
    """The type with its article: 'an int', 'a dir' ('an unknown' for None)."""
    name = type_.value if type_ is not None else "unknown"
    return f"an {name}" if name[0] in "aeiou" else f"a {name}"


def _binary(env: Env, expr: ast.Binary) -> Result:
    left_type, left = check_expr(env, expr.left)
    right_type, right = check_expr(env, expr.right)
    op = expr.op
    operator = BINARY[op]
    result = operator.result
    if left_type is None or right_type is None:
        return result, None
    if not _types_fit(operator.operands, left_type, right_type):
        env.ctx.report(codes.TYPE_MISMATCH, expr.op_span,
                       f"'{op}' cannot combine {a_type(left_type)} with {a_type(right_type)}; "
                       f"{_HINTS[operator.operands]}",
                       related=(diag.Related(expr.left.span, f"this is {a_type(left_type)}"),
                                diag.Related(expr.right.span, f"this is {a_type(right_type)}")))
        return result, None
    if op in DIVISIONS and right is not None and right.value == 0:
        env.ctx.report(codes.DIVISION_BY_ZERO, expr.right.span,
                       f"'{op}' by zero{where(env, expr.right)}: the divisor is the constant 0")
        return result, None
    if left is None or right is None:
        return result, None
    # exact, not wrapped: a constant outside -128..127 is an error (docs/language.md), never a wrap
    value = operator.exact(left.value, right.value)
    if result is Type.INT:
        return _ranged(env, expr, value)
    return result, Value(result, value)


def _types_fit(operands: str, left: Type, right: Type) -> bool:
    if operands == "int":
        return left is Type.INT and right is Type.INT
    if operands == "bool":
        return left is Type.BOOL and right is Type.BOOL
    if operands == "same":
        return left is right and left in _COMPARABLE
    pair = {left, right}
    return pair == {Type.INT} or pair == {Type.INT, Type.CONNSET}


_HINTS = {  # by the operands of BINARY
    "int": "arithmetic needs two ints",
    "bool": "logic needs two bools",
    "same": "both sides must have the same type (use sizeof(s) to count a connset)",
    "ordered": "compare ints, or a connset with an int",
}
