"""Layout: turns a code list into bytes. Embedded bodies follow the code that names them; each
body is laid out with its own nested bodies, its jump targets and ranges relative to its own
start (it runs as a program of its own). Identical bodies share one range."""

from __future__ import annotations

from rdcd_core.compiler.ir import Body, Ins, Item, Label, bodies_of, code_size, encode
from rdcd_core.compiler.program import SourceEntry


def assemble(code: list[Item]) -> tuple[bytes, list[SourceEntry]]:
    """Bytes of ``code`` with its bodies, and one source entry per instruction."""
    labels: dict[int, int] = {}
    offset = 0
    for item in code:
        if type(item) is Label:
            labels[id(item)] = offset
        else:
            offset += item.size
    blob = bytearray()
    tail = bytearray()
    tail_entries: list[SourceEntry] = []
    ranges: dict[int, tuple[int, int]] = {}
    placed: dict[bytes, int] = {}
    main_size = offset  # the main code's size, summed above
    for body in bodies_of(code):
        ranges[id(body)] = _place(body, main_size, tail, tail_entries, placed)
    entries: list[SourceEntry] = []
    add_entry = entries.append
    for item in code:
        if type(item) is Ins:
            encoded = encode(item, labels, ranges)
            add_entry(SourceEntry(len(blob), item.size, item.span))
            blob += encoded
    return bytes(blob + tail), entries + tail_entries


def _assembled(body: Body) -> tuple[bytes, list[SourceEntry]]:
    if body.assembled is None or not body.optimised:  # final code is laid out once
        body.assembled = assemble(body.code)
    return body.assembled


def laid_out_size(code: list[Item]) -> int:
    """``len(assemble(code)[0])`` without making the source entries (the planner's trials)."""
    placed: set[bytes] = set()
    total = code_size(code)
    for body in bodies_of(code):
        blob = _assembled(body)[0]
        if blob not in placed:
            placed.add(blob)
            total += len(blob)
    return total


def _place(body: Body, base: int, tail: bytearray, entries: list[SourceEntry],
           placed: dict[bytes, int]) -> tuple[int, int]:
    code, sub_entries = _assembled(body)
    if code in placed:
        return placed[code], len(code)
    start = base + len(tail)
    placed[code] = start
    tail += code
    entries.extend(SourceEntry(start + e.offset, e.size, e.span) for e in sub_entries)
    return start, len(code)


def size_bound(code: list[Item]) -> int:
    """At least the size of ``code`` once optimised and laid out: no peephole pass makes code
    larger and layout only shares bodies. Lets the planner settle most trials without optimising."""
    total = code_size(code)
    for body in bodies_of(code):
        total += len(body.assembled[0]) if body.optimised and body.assembled else size_bound(body.code)
    return total


def fragment_size(code: list[Item]) -> int:
    return len(assemble(code)[0])
