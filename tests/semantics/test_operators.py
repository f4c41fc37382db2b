"""The one operator table (rdcd_core.operators): it names the grammar's operators, computes what the
VM's interpreter computes, and the checker, the conflict analysis and the compiler all read it."""

from __future__ import annotations

import ast as python_ast
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

import rdcd_core
from rdcd_core.operators import BINARY, UNARY
from rdcd_core.syntax import context
from rdcd_core.types import INT8_MAX, INT8_MIN
from vm.interpreter import Frame, Outcome, run
from vm.isa.assembler import assemble

BYTES = st.integers(INT8_MIN, INT8_MAX)
# how the compiler computes each operator with the VM's instructions (&&, || and ! are jumps)
_CODE = {"+": "ADD", "-": "SUB", "*": "MUL", "/": "DIV", "%": "MOD", "==": "EQUALS", "<": "LESSER",
         ">": "GREATER"}
_DIVISIONS = {"/", "%"}
_BOOLS = {"&&", "||"}
_READERS = ("compiler/fold.py", "semantics/conflicts.py", "semantics/expressions.py")


class _Nothing:
    def __getattr__(self, name: str):  # noqa: ANN204
        return lambda *args: 0


def on_the_vm(lines: list[str]) -> int:
    frame = Frame(assemble("\n".join([*lines, "END_TERMINATE"])))
    assert run(frame, _Nothing()).outcome is Outcome.TERMINATE
    (value,) = frame.stack
    return value


def test_the_table_has_the_grammars_operators() -> None:
    binary = {context.TOKEN_TEXT[name].strip("'") for name in context.OPERATORS}
    assert set(BINARY) == binary
    assert set(UNARY) == {context.TOKEN_TEXT[name].strip("'") for name in ("MINUS", "BANG")}


@given(st.sampled_from(sorted(_CODE)), BYTES, BYTES)
def test_arithmetic_and_comparisons_compute_as_the_vm(op: str, a: int, b: int) -> None:
    if op in _DIVISIONS and b == 0:
        return  # a runtime error on the VM, never folded (tests/vm/test_runtime_values.py)
    assert BINARY[op].apply(a, b) == on_the_vm([f"PUSHC {a}", f"PUSHC {b}", _CODE[op]])


@given(BYTES)
def test_negation_computes_as_the_vm(a: int) -> None:
    assert UNARY["-"].apply(a) == on_the_vm([f"PUSHC {a}", "NEGATE"])


@given(st.sampled_from(sorted(BINARY)), BYTES, BYTES)
def test_every_result_is_a_vm_value(op: str, a: int, b: int) -> None:
    if op in _BOOLS:
        a, b = a & 1, b & 1
    if op in _DIVISIONS and b == 0:
        b = 1
    value = BINARY[op].apply(a, b)
    assert INT8_MIN <= value <= INT8_MAX
    assert BINARY[op].exact(a, b) == value or BINARY[op].result.value == "int"


def test_the_readers_keep_no_table_of_their_own() -> None:
    """No operator symbol is written as a dict key or compared with in the three readers."""
    root = Path(rdcd_core.__file__).parent
    symbols = set(BINARY) | set(UNARY)
    for name in _READERS:
        tree = python_ast.parse((root / name).read_text(encoding="utf-8"))
        for node in python_ast.walk(tree):
            if isinstance(node, python_ast.Dict):
                keys = {k.value for k in node.keys if isinstance(k, python_ast.Constant)}
                assert not keys & symbols, (name, node.lineno)
            if isinstance(node, python_ast.Compare):
                constants = [c.value for c in python_ast.walk(node) if isinstance(c, python_ast.Constant)]
                assert not set(constants) & symbols - {"-", "!"}, (name, node.lineno)
        assert "from rdcd_core.operators import" in (root / name).read_text(encoding="utf-8"), name


def test_a_deciding_left_operand_decides_the_value() -> None:
    deciding = [op for op in BINARY.values() if op.decides is not None]
    assert {op.symbol for op in deciding} == _BOOLS
    for op in deciding:
        assert all(op.apply(int(op.decides), b) == int(op.decides) for b in (0, 1))
