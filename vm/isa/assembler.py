"""Text → bytes for DCD-VM fragments.

Syntax: one instruction per line; ``;`` or ``#`` starts a comment; ``name:`` defines a label
(alone or before an instruction). Operands are separated by spaces or commas and are numbers
(``12``, ``-3``, ``0x1F``), symbolic names (directions ``EAST`` … ``DOWN``, events
``EVENT_PROXIMITY_k``, commands ``ROTATE_CW ROTATE_CCW STOP ROTATE_DEGREES ROTATE_TO USER_k``,
roles ``ANY``/``NONE``), labels (a label is its byte offset, usable for jump targets and code
starts) or a label difference ``end-start`` (for sizes). ``PUSH n`` chooses the one-byte form
128+n for 0..127 and ``PUSHC n`` otherwise; ``.byte n ...`` emits raw bytes.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from vm.isa.opcodes import BUILTIN_COMMANDS, BY_NAME, PUSH_SMALL_BASE, USER_COMMAND_NUMBERS
from vm.navigation import DIRECTION_BY_NAME
from vm.roles import ANY_ROLE, NO_ROLE

COMMAND_NAMES = {name: code for code, name in BUILTIN_COMMANDS.items()}
COMMAND_NAMES.update({f"USER_{k}": code for k, code in enumerate(USER_COMMAND_NUMBERS)})
SYMBOLS: dict[str, int] = {**DIRECTION_BY_NAME, **COMMAND_NAMES, "ANY": ANY_ROLE, "NONE": NO_ROLE}
SYMBOLS.update({f"EVENT_PROXIMITY_{k}": k for k in range(8)})

_LABEL = re.compile(r"^([A-Za-z_][A-Za-z_0-9.]*):")


# The project's one definition of a line (the LSP's, rdcd_core.source): \r\n, \r or \n; form feed,
# U+2028 and the other breaks of str.splitlines are ordinary characters (in a comment, say).
_LINE_BREAK = re.compile("\r\n|\r|\n")


class AssemblyError(ValueError):
    pass


@dataclass
class _Line:
    number: int
    mnemonic: str
    args: list[str]
    offset: int = 0
    size: int = 0


def _parse(text: str) -> tuple[list[_Line], dict[str, int]]:
    lines: list[_Line] = []
    pending: list[tuple[str, int]] = []
    labels: dict[str, int] = {}
    offset = 0
    for number, raw in enumerate(_LINE_BREAK.split(text), 1):
        line = re.split(r"[;#]", raw, maxsplit=1)[0].strip()
        while (m := _LABEL.match(line)) is not None:
            pending.append((m.group(1), number))
            line = line[m.end():].strip()
        if not line:
            continue
        parts = line.replace(",", " ").split()
        item = _Line(number, parts[0].upper(), parts[1:], offset)
        item.size = _size(item)
        for name, at in pending:
            if name in labels:
                raise AssemblyError(f"line {at}: label {name!r} defined twice")
            labels[name] = offset
        pending.clear()
        lines.append(item)
        offset += item.size
    for name, at in pending:
        if name in labels:
            raise AssemblyError(f"line {at}: label {name!r} defined twice")
        labels[name] = offset
    return lines, labels


def _size(item: _Line) -> int:
    if item.mnemonic == ".BYTE":
        if not item.args:
            raise AssemblyError(f"line {item.number}: .byte needs at least one value")
        return len(item.args)
    if item.mnemonic == "PUSH":
        if len(item.args) != 1:
            raise AssemblyError(f"line {item.number}: PUSH takes one operand")
        value = _number(item.args[0])
        return 1 if value is not None and 0 <= value <= 127 else 2
    ins = BY_NAME.get(item.mnemonic)
    if ins is None:
        raise AssemblyError(f"line {item.number}: unknown instruction {item.mnemonic!r}")
    if len(item.args) != len(ins.operands):
        raise AssemblyError(f"line {item.number}: {ins.name} takes {len(ins.operands)} operand(s), "
                            f"got {len(item.args)}")
    return ins.size


def _number(token: str) -> int | None:
    try:
        return int(token, 0)
    except ValueError:
        return None


def _value(token: str, labels: dict[str, int], number: int) -> int:
    n = _number(token)
    if n is not None:
        return n
    if token.upper() in SYMBOLS:
        return SYMBOLS[token.upper()]
    if token in labels:
        return labels[token]
    if "-" in token:
        a, b = token.split("-", 1)
        return _value(a, labels, number) - _value(b, labels, number)
    raise AssemblyError(f"line {number}: unknown name {token!r}")


def _byte(value: int, number: int) -> int:
    if not -128 <= value <= 255:
        raise AssemblyError(f"line {number}: operand {value} does not fit in a byte")
    return value & 0xFF


def assemble(text: str) -> bytes:
    """Assemble a fragment; raises AssemblyError naming the line of the first problem."""
    lines, labels = _parse(text)
    out = bytearray()
    for item in lines:
        values = [_byte(_value(a, labels, item.number), item.number) for a in item.args]
        if item.mnemonic == ".BYTE":
            out.extend(values)
        elif item.mnemonic == "PUSH":
            if item.size == 1:
                out.append(PUSH_SMALL_BASE + values[0])
            else:
                out.extend((BY_NAME["PUSHC"].opcode, values[0]))
        else:
            out.append(BY_NAME[item.mnemonic].opcode)
            out.extend(values)
    return bytes(out)

