"""The LSP's lines and positions written out the slow, obvious way, for tests to compare with.

Independent of ``rdcd_core.source`` on purpose: a line ends at ``\\r\\n``, ``\\r`` or ``\\n``;
every other character, form feed and U+2028 included, is part of a line. Columns count code units
of the position encoding: UTF-8 bytes, UTF-16 units or code points (UTF-32).
"""

from __future__ import annotations

# Everything that str.splitlines (or some editor) takes for a line break; only the first three are.
LINE_BREAK_LIKE = ["\n", "\r", "\r\n", "\v", "\f", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"]
NOT_LINE_BREAKS = ["\v", "\f", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"]
ENCODINGS = ["utf-8", "utf-16", "utf-32"]


def lines(text: str) -> list[tuple[int, int]]:
    """(start, end) of every line, the end before its line break."""
    found = []
    start = i = 0
    while i < len(text):
        if text[i] == "\r" and text[i + 1:i + 2] == "\n":
            found.append((start, i))
            i += 2
            start = i
        elif text[i] in "\r\n":
            found.append((start, i))
            i += 1
            start = i
        else:
            i += 1
    found.append((start, len(text)))
    return found


def units(text: str, encoding: str) -> int:
    if encoding == "utf-8":
        return len(text.encode("utf-8"))
    if encoding == "utf-16":
        return len(text.encode("utf-16-le")) // 2
    return len(text)


def position(text: str, offset: int, encoding: str = "utf-16") -> tuple[int, int]:
    """The (line, character) of an offset that is not inside a ``\\r\\n``."""
    for number, (start, end) in enumerate(lines(text)):
        if start <= offset <= end:
            return number, units(text[start:offset], encoding)
    raise ValueError(f"offset {offset} is inside a line break")


def offset(text: str, line: int, character: int, encoding: str = "utf-16") -> int:
    """The offset of a position, clamped as the LSP says (past a line's end: its end; past the
    last line: the end of the text). A position inside a character counts as after it."""
    found = lines(text)
    if line >= len(found):
        return len(text)
    start, end = found[line]
    at = start
    while at < end and units(text[start:at], encoding) < character:
        at += 1
    return at
