"""Shared tails (cross-jumping): two identical instruction runs that end the flow (END_*,
MIGRATE_CONTINUE, GOTO) keep one copy; the other becomes a GOTO to it when that is smaller."""

from __future__ import annotations

from rdcd_core.compiler.ir import Ins, Item, Label

GOTO_SIZE = 2


def merge_tails(code: list[Item]) -> list[Item]:
    """Merges one pair: the latest end that has an earlier twin, with the earliest such twin.

    Two ends share a tail worth a GOTO exactly when their shortest runs of more than GOTO_SIZE
    bytes are identical (``_signature``) and do not overlap, so the pair is found with a table of
    first occurrences instead of comparing every pair of ends (quadratic in the number of ends).
    """
    ends = [i for i, item in enumerate(code) if type(item) is Ins and item.ends_flow]
    signatures = [_signature(code, end) for end in ends]
    first: dict[tuple, int] = {}
    for end, signature in zip(ends, signatures, strict=True):
        if signature is not None:
            first.setdefault(signature, end)
    for later, signature in zip(reversed(ends), reversed(signatures), strict=True):
        if signature is None:
            continue
        earlier = first[signature]
        # the runs may not overlap: the later one starts after the earlier one ends
        if later - earlier >= len(signature):
            return _replace(code, earlier, later, _common_run(code, earlier, later))
    return code


def _signature(code: list[Item], end: int) -> tuple | None:
    """Keys of the fewest instructions ending at ``end`` (no label between them) that are more
    than GOTO_SIZE bytes; None when a label or the start comes first. A run that ends at ``end``
    saves more than a GOTO exactly when it holds these instructions."""
    keys: list[tuple] = []
    size = 0
    index = end
    while size <= GOTO_SIZE:
        if index < 0 or type(code[index]) is not Ins:
            return None
        keys.append(code[index].key())
        size += code[index].size
        index -= 1
    return tuple(keys)


def _common_run(code: list[Item], a: int, b: int) -> int:
    """Instructions (no labels between them) that end at a and at b and are identical."""
    length = 0
    while a - length >= 0 and b - length > a:
        x, y = code[a - length], code[b - length]
        if not (type(x) is Ins and type(y) is Ins) or x.key() != y.key():
            break
        length += 1
    return length


def _replace(code: list[Item], earlier: int, later: int, length: int) -> list[Item]:
    start = earlier - length + 1
    label = Label("tail")
    result = code[:start] + [label] + code[start:later - length + 1]
    result.append(Ins("GOTO", (label,), code[later].span))
    return result + code[later + 1:]
