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


@dataclass(slots=True)
class Ins:
    op: str
    args: tuple = ()
    span: Span | None = None

    @property
    def size(self) -> int:
        if self.op == "PUSH":
            return 1 if 0 <= self.args[0] <= 127 else 2
        return BY_NAME[self.op].size

    @property
    def ends_flow(self) -> bool:
        return self.op != "PUSH" and BY_NAME[self.op].no_fallthrough

    @property
    def target(self) -> Label | None:
        return self.args[0] if self.op in JUMPS else None

    def key(self) -> tuple:
        """Identity of the instruction for comparisons (labels and bodies by identity)."""
        return (self.op, tuple(id(a) if isinstance(a, (Label, Body)) else a for a in self.args))


Item = Union[Ins, Label]
JUMPS = {"GOTO", "IF_FALSE_GOTO", "IF_TRUE_GOTO"}
COND_JUMPS = {"IF_FALSE_GOTO", "IF_TRUE_GOTO"}


def code_size(code: list[Item]) -> int:
    return sum(item.size for item in code if isinstance(item, Ins))


def bodies_of(code: list[Item]) -> list[Body]:
    found: list[Body] = []
    for item in code:
        if isinstance(item, Ins):
            found.extend(a for a in item.args if isinstance(a, Body) and a not in found)
    return found


def encode(ins: Ins, labels: dict[int, int], ranges: dict[int, tuple[int, int]]) -> bytes:
    if ins.op == "PUSH":
        value = ins.args[0]
        if 0 <= value <= 127:
            return bytes([PUSH_SMALL_BASE + value])
        return bytes([BY_NAME["PUSHC"].opcode, value & 0xFF])
    out = [BY_NAME[ins.op].opcode]
    for arg in ins.args:
        if isinstance(arg, Label):
            out.append(labels[id(arg)])
        elif isinstance(arg, Body):
            out.extend(ranges[id(arg)])
        else:
            out.append(arg)
    # Offsets past 255 only occur in code far over the 64-byte slot (reported as E601); the
    # planner still needs its size, so every operand is kept to one byte.
    return bytes(b & 0xFF for b in out)
