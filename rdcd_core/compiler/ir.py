"""The compiler's intermediate code: instructions with symbolic labels and embedded bodies.

A code list holds ``Ins`` and ``Label`` items. ``PUSH v`` is a pseudo instruction: one byte
(128 + v) for 0 <= v <= 127, else ``PUSHC``. ``HANDLE_EVENT e body`` and ``INSTALL_COMMAND role cmd
body`` name a ``Body`` (its own code list); layout appends bodies after the main code and fills
in start and size.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from rdcd_core.source import Span
from vm.isa.opcodes import BY_NAME, PUSH_SMALL_BASE


@dataclass(eq=False, slots=True)
class Label:
    hint: str = ""

    def __repr__(self) -> str:
        return f"L{id(self) % 10000}"


@dataclass(eq=False, slots=True)
class Body:
    code: list[Item] = field(default_factory=list)
    # set by the peephole optimiser once ``code`` is final; layout then keeps its bytes
    optimised: bool = False
    assembled: tuple | None = None


@dataclass(slots=True)
class Ins:
    op: str
    args: tuple = ()
    span: Span | None = None
    _key: tuple | None = field(default=None, init=False, repr=False, compare=False)

    @property
    def size(self) -> int:
        if self.op == "PUSH":
            return 1 if 0 <= self.args[0] <= 127 else 2
        return _SIZES[self.op]

    @property
    def ends_flow(self) -> bool:
        return self.op in ENDS_FLOW

    @property
    def target(self) -> Label | None:
        return self.args[0] if self.op in JUMPS else None

    def key(self) -> tuple:
        """Identity of the instruction for comparisons (labels and bodies by identity)."""
        if self._key is None:  # an instruction is never changed, only replaced
            self._key = (self.op, tuple(id(a) if isinstance(a, (Label, Body)) else a for a in self.args))
        return self._key


_SIZES = {name: instruction.size for name, instruction in BY_NAME.items()}  # read for every pass
_ALONE = {name: bytes([instruction.opcode]) for name, instruction in BY_NAME.items()}  # no operands
_OPCODES = {name: instruction.opcode for name, instruction in BY_NAME.items()}
ENDS_FLOW = frozenset(name for name, instruction in BY_NAME.items() if instruction.no_fallthrough)
Item = Union[Ins, Label]
JUMPS = {"GOTO", "IF_FALSE_GOTO", "IF_TRUE_GOTO"}
COND_JUMPS = {"IF_FALSE_GOTO", "IF_TRUE_GOTO"}


def code_size(code: list[Item]) -> int:
    return sum(item.size for item in code if type(item) is Ins)


def bodies_of(code: list[Item]) -> list[Body]:
    found: dict[int, Body] = {}  # by identity, in order of first use
    for item in code:
        if type(item) is Ins:
            for arg in item.args:
                if type(arg) is Body:
                    found.setdefault(id(arg), arg)
    return list(found.values())


def encode(ins: Ins, labels: dict[int, int], ranges: dict[int, tuple[int, int]]) -> bytes:
    if ins.op == "PUSH":
        value = ins.args[0]
        if 0 <= value <= 127:
            return bytes([PUSH_SMALL_BASE + value])
        return bytes([BY_NAME["PUSHC"].opcode, value & 0xFF])
    if not ins.args:
        return _ALONE[ins.op]
    out = [_OPCODES[ins.op]]
    for arg in ins.args:
        if type(arg) is Label:
            out.append(labels[id(arg)] & 0xFF)
        elif type(arg) is Body:
            out.extend([b & 0xFF for b in ranges[id(arg)]])
        else:
            out.append(arg & 0xFF)
    # Offsets past 255 only occur in code far over the 64-byte slot (reported as E601); the
    # planner still needs its size, so every operand is kept to one byte.
    return bytes(out)
