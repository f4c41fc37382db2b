"""Shared tails (cross-jumping): two identical instruction runs that end the flow (END_*,
MIGRATE_CONTINUE, GOTO) keep one copy; the other becomes a GOTO to it when that is smaller."""

from __future__ import annotations

from rdcd_core.compiler.ir import Ins, Item, Label

GOTO_SIZE = 2


def merge_tails(code: list[Item]) -> list[Item]:
    ends = [i for i, item in enumerate(code) if isinstance(item, Ins) and item.ends_flow]
    for later in reversed(ends):
        for earlier in ends:
            if earlier >= later:
                break
            length = _common_run(code, earlier, later)
            saved = sum(code[later - k].size for k in range(length))
            if length and saved > GOTO_SIZE:
                return _replace(code, earlier, later, length)
    return code


def _common_run(code: list[Item], a: int, b: int) -> int:
    """Instructions (no labels between them) that end at a and at b and are identical."""
    length = 0
    while a - length >= 0 and b - length > a:
        x, y = code[a - length], code[b - length]
        if not (isinstance(x, Ins) and isinstance(y, Ins)) or x.key() != y.key():
            break
        length += 1
    return length


def _replace(code: list[Item], earlier: int, later: int, length: int) -> list[Item]:
    start = earlier - length + 1
    label = Label("tail")
    result = code[:start] + [label] + code[start:later - length + 1]
    result.append(Ins("GOTO", (label,), code[later].span))
    return result + code[later + 1:]
