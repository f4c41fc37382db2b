"""The operators of RDCD (docs/language.md): one table that the checker's constant folding, the
conflict analysis and the compiler's folding all read (docs/architecture.md rule 1).

Values are the DCD-VM's: signed bytes. ``apply`` computes what the VM computes: ``+``, ``-``, ``*``, ``/`` and
negation saturate at -128..127 like its ADD and SUB (``vm.isa.opcodes.saturated``); comparisons
give 1 or 0 like its GREATER, LESSER and EQUALS; ``&&``, ``||`` and ``!`` take any non-zero value as
true, like its conditional jumps. ``exact`` is the mathematical result before the wrap: the checker
folds constants with it, since a constant outside -128..127 is an error rather than a wrapped value.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from rdcd_core.types import Type
from vm.isa.opcodes import saturated


@dataclass(frozen=True, slots=True)
class BinaryOperator:
    symbol: str
    operands: str  # "int" (+ -), "bool" (&& ||), "same" (== !=), "ordered" (< > <= >=)
    result: Type
    exact: Callable[[int, int], int]
    decides: bool | None = None  # && and ||: the truth of the left operand that decides alone

    def apply(self, a: int, b: int) -> int:
        """The value the VM computes for ``a op b``."""
        value = self.exact(a, b)
        return saturated(value) if self.result is Type.INT else value


@dataclass(frozen=True, slots=True)
class UnaryOperator:
    symbol: str
    operand: Type
    exact: Callable[[int], int]

    def apply(self, a: int) -> int:
        value = self.exact(a)
        return saturated(value) if self.operand is Type.INT else value


def _quotient(a: int, b: int) -> int:
    """``a / b`` rounded toward zero (b != 0: the checker and the compiler never fold a zero divisor)."""
    quotient = abs(a) // abs(b)
    return quotient if (a < 0) == (b < 0) else -quotient


DIVISIONS = frozenset({"/", "%"})  # a zero divisor: E213 for a constant, a runtime error otherwise

BINARY: dict[str, BinaryOperator] = {op.symbol: op for op in (
    BinaryOperator("+", "int", Type.INT, lambda a, b: a + b),
    BinaryOperator("-", "int", Type.INT, lambda a, b: a - b),
    # * / % (issue 25): / rounds toward zero as C does and % takes the sign of the dividend, so that
    # a == (a / b) * b + a % b; a zero divisor has no value (``divides``)
    BinaryOperator("*", "int", Type.INT, lambda a, b: a * b),
    BinaryOperator("/", "int", Type.INT, lambda a, b: _quotient(a, b)),
    BinaryOperator("%", "int", Type.INT, lambda a, b: a - b * _quotient(a, b)),
    BinaryOperator("&&", "bool", Type.BOOL, lambda a, b: int(bool(a) and bool(b)), decides=False),
    BinaryOperator("||", "bool", Type.BOOL, lambda a, b: int(bool(a) or bool(b)), decides=True),
    BinaryOperator("==", "same", Type.BOOL, lambda a, b: int(a == b)),
    BinaryOperator("!=", "same", Type.BOOL, lambda a, b: int(a != b)),
    BinaryOperator("<", "ordered", Type.BOOL, lambda a, b: int(a < b)),
    BinaryOperator(">", "ordered", Type.BOOL, lambda a, b: int(a > b)),
    BinaryOperator("<=", "ordered", Type.BOOL, lambda a, b: int(a <= b)),
    BinaryOperator(">=", "ordered", Type.BOOL, lambda a, b: int(a >= b)),
)}

UNARY: dict[str, UnaryOperator] = {op.symbol: op for op in (
    UnaryOperator("-", Type.INT, lambda a: -a),
    UnaryOperator("!", Type.BOOL, lambda a: int(not a)),
)}
