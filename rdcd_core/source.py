"""Source text positions: spans are character offsets; LineIndex turns them into lines and columns.

One definition of "line" for the whole project, the Language Server Protocol's: a line ends at
``\\n``, ``\\r\\n`` or a lone ``\\r`` and nowhere else. Form feed, vertical tab, U+0085, U+2028,
U+2029 and the other characters Python's ``str.splitlines`` also splits on are ordinary characters
inside a line. Every place that splits a text into lines uses this module.

Conversion to LSP positions (UTF-16 columns) happens only in ``server/`` (docs/architecture.md rule 3).
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass

from rdcd_core.fastinit import fast_init

LINE_BREAK = re.compile(r"\r\n?|\n")
"""A line break: ``\\r\\n`` is one break, a ``\\r`` or ``\\n`` alone is one too."""
_LF = re.compile("\n")
_CR = re.compile("\r")


def split_lines(text: str, keepends: bool = False) -> list[str]:
    """The lines of ``text``. Without ``keepends``, a text of n line breaks gives n + 1 lines (the
    last one empty when the text ends with a break); with it, the pieces join to ``text`` again
    and there is no empty last piece (as ``str.splitlines(True)``, but splitting on line breaks only)."""
    if not keepends:
        return LINE_BREAK.split(text)
    pieces: list[str] = []
    start = 0
    for match in LINE_BREAK.finditer(text):
        pieces.append(text[start:match.end()])
        start = match.end()
    if start < len(text):
        pieces.append(text[start:])
    return pieces


def count_line_breaks(text: str, start: int = 0, end: int | None = None) -> int:
    """How many line breaks ``text[start:end]`` holds (a ``\\r\\n`` counts once)."""
    stop = len(text) if end is None else end
    if "\r" not in text:
        return text.count("\n", start, stop)
    return sum(1 for _ in LINE_BREAK.finditer(text, start, stop))


def has_line_break(text: str) -> bool:
    return "\n" in text or "\r" in text


def newline_of(text: str) -> str:
    """The line break a text uses: its first one, ``\\n`` when it has none."""
    match = LINE_BREAK.search(text)
    return match.group() if match else "\n"


def normalize_newlines(text: str, newline: str = "\n") -> str:
    """``text`` with every line break written as ``newline``."""
    if "\r" not in text and newline == "\n":
        return text
    return LINE_BREAK.sub(newline, text)


# Characters that move a terminal's cursor or that terminals draw as nothing; a source line quoted
# in a diagnostic shows each as one visible character, so that the caret under it stays in place.
_VISIBLE = {code: 0x2400 + code for code in range(0x20) if code != 0x09}  # the Control Pictures block
_VISIBLE.update({0x7F: 0x2421, 0x85: 0x2424, 0x2028: 0x2424, 0x2029: 0x00B6})


def visible(line: str) -> str:
    """A line fit to print under a diagnostic: control characters and invisible breaks shown as symbols
    (form feed as ␌, U+2028 as ␤, ...), one character for one, so columns do not move."""
    return line.translate(_VISIBLE)


@fast_init
@dataclass(frozen=True, slots=True)
class Span:
    """Half-open range ``[start, end)`` of character offsets into a source text."""

    start: int
    end: int

    def cover(self, other: Span) -> Span:
        return Span(min(self.start, other.start), max(self.end, other.end))

    def contains(self, offset: int) -> bool:
        return self.start <= offset <= self.end


@fast_init
@dataclass(frozen=True, slots=True)
class LineCol:
    """Zero-based line and zero-based column counted in Unicode code points."""

    line: int
    column: int


class LineIndex:
    """Maps offsets of one text to zero-based (line, column) and back, lines as the LSP defines them."""

    def __init__(self, text: str) -> None:
        self.text = text
        # A plain search is much faster than LINE_BREAK's alternation: a text without lone \r (no \r,
        # or every \r in a \r\n) has its line starts after each \n, one without \n after each \r.
        if "\r" not in text or text.count("\r") == text.count("\r\n"):
            pattern = _LF
        else:
            pattern = _CR if "\n" not in text else LINE_BREAK
        self.line_starts = [0, *[match.end() for match in pattern.finditer(text)]]

    def line_col(self, offset: int) -> LineCol:
        offset = max(0, min(offset, len(self.text)))
        line = bisect.bisect_right(self.line_starts, offset) - 1
        return LineCol(line, offset - self.line_starts[line])

    def line_end(self, line: int) -> int:
        """The offset where the text of ``line`` ends, before its line break."""
        if line + 1 >= len(self.line_starts):
            return len(self.text)
        end = self.line_starts[line + 1] - 1
        if end > self.line_starts[line] and self.text[end] == "\n" and self.text[end - 1] == "\r":
            end -= 1
        return end

    def offset(self, line: int, column: int) -> int:
        """Offset of (line, column), clamped into the text and to the line (never inside its break)."""
        if line < 0:
            return 0
        if line >= len(self.line_starts):
            return len(self.text)
        start = self.line_starts[line]
        return start + max(0, min(column, self.line_end(line) - start))

    def line_text(self, line: int) -> str:
        """The text of ``line`` without its line break."""
        if line < 0 or line >= len(self.line_starts):
            return ""
        return self.text[self.line_starts[line]:self.line_end(line)]

    @property
    def line_count(self) -> int:
        return len(self.line_starts)
