"""Bytes → instructions (and text the assembler reads back to the same bytes).

Decoding is linear from offset 0: a known opcode consumes its operands; a byte >= 128 is
"push constant (byte - 128)"; anything else (unknown opcode, or an opcode whose operands are cut
off by the end of the fragment) is a raw ``.byte``.
"""

from __future__ import annotations

from dataclasses import dataclass

from vm.isa.opcodes import BY_OPCODE, PUSH_SMALL_BASE, Instruction, Operand

PUSH_SMALL = "PUSH"  # name of the one-byte push constant form
RAW = ".byte"


@dataclass(frozen=True, slots=True)
class Decoded:
    offset: int
    opcode: int
    name: str  # instruction name, "PUSH" for a one-byte constant, ".byte" for raw data
    operands: tuple[int, ...]
    info: Instruction | None

    @property
    def size(self) -> int:
        return 1 + len(self.operands)

    @property
    def raw(self) -> bool:
        return self.name == RAW


def decode_at(code: bytes, offset: int) -> Decoded:
    op = code[offset]
    if op >= PUSH_SMALL_BASE:
        return Decoded(offset, op, PUSH_SMALL, (op - PUSH_SMALL_BASE,), None)
    info = BY_OPCODE.get(op)
    if info is None or offset + info.size > len(code):
        return Decoded(offset, op, RAW, (op,), None)
    return Decoded(offset, op, info.name, tuple(code[offset + 1: offset + info.size]), info)


def disassemble(code: bytes) -> list[Decoded]:
    out: list[Decoded] = []
    offset = 0
    while offset < len(code):
        d = decode_at(code, offset)
        out.append(d)
        offset += 1 if d.raw or d.name == PUSH_SMALL else d.size
    return out


def boundaries(code: bytes) -> set[int]:
    """Offsets where instructions start in the linear decoding (plus the end of the code)."""
    return {d.offset for d in disassemble(code)} | {len(code)}


def _operand_text(kind: Operand, value: int, labels: dict[int, str]) -> str:
    if kind is Operand.TARGET and value in labels:
        return labels[value]
    return str(value)


def reachable(code: bytes) -> set[int]:
    """Offsets of the instructions that control can reach from offset 0 (embedded handler and
    command bodies are not reached: they run as programs of their own)."""
    at = {d.offset: d for d in disassemble(code)}
    seen: set[int] = set()
    work = [0] if code else []
    while work:
        pc = work.pop()
        if pc in seen or pc not in at:
            continue
        seen.add(pc)
        work.extend(successors(at[pc]))
    return seen


def successors(d: Decoded) -> list[int]:
    """Offsets control can go to after ``d``: the next instruction unless ``d`` never falls
    through, and its jump target (an unknown byte is skipped as one byte)."""
    if d.info is None:
        return [d.offset + 1]
    out = [] if d.info.no_fallthrough else [d.offset + d.size]
    if Operand.TARGET in d.info.operands:
        out.append(d.operands[d.info.operands.index(Operand.TARGET)])
    return out


def to_text(code: bytes, *, with_offsets: bool = False) -> str:
    """Text listing; jump targets of reachable instructions that land on instruction starts get
    labels ``L<offset>`` (targets inside embedded bodies are relative to the body: kept as numbers)."""
    decoded = disassemble(code)
    starts = {d.offset for d in decoded}
    live = reachable(code)
    labels: dict[int, str] = {}
    for d in decoded:
        if d.info is None or d.offset not in live:
            continue
        for kind, value in zip(d.info.operands, d.operands, strict=True):
            if kind is Operand.TARGET and value in starts:
                labels[value] = f"L{value}"
    lines: list[str] = []
    for d in decoded:
        if d.offset in labels:
            lines.append(f"{labels[d.offset]}:")
        if d.info is None:
            body = f"{d.name} {d.operands[0]}"
        else:
            ops = [_operand_text(k, v, labels) for k, v in zip(d.info.operands, d.operands, strict=True)]
            body = " ".join([d.name, *ops]) if ops else d.name
        lines.append(f"    {body:<32} ; {d.offset}" if with_offsets else f"    {body}")
    return "\n".join(lines) + ("\n" if lines else "")
