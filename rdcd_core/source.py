"""Source text positions: spans are character offsets; LineIndex turns them into lines and columns.

Conversion to LSP positions (UTF-16 columns) happens only in ``server/`` (DESIGN.md rule 3).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass

from rdcd_core.fastinit import fast_init


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
    """Maps offsets of one text to zero-based (line, column) and back."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.line_starts = [0]
        find = text.find
        newline = find("\n")
        while newline >= 0:
            self.line_starts.append(newline + 1)
            newline = find("\n", newline + 1)

    def line_col(self, offset: int) -> LineCol:
        offset = max(0, min(offset, len(self.text)))
        line = bisect.bisect_right(self.line_starts, offset) - 1
        return LineCol(line, offset - self.line_starts[line])

    def offset(self, line: int, column: int) -> int:
        """Offset of (line, column), clamped into the text."""
        if line < 0:
            return 0
        if line >= len(self.line_starts):
            return len(self.text)
        start = self.line_starts[line]
        end = self.line_starts[line + 1] - 1 if line + 1 < len(self.line_starts) else len(self.text)
        return start + max(0, min(column, end - start))

    def line_text(self, line: int) -> str:
        if line < 0 or line >= len(self.line_starts):
            return ""
        start = self.line_starts[line]
        end = self.line_starts[line + 1] - 1 if line + 1 < len(self.line_starts) else len(self.text)
        return self.text[start:end]

    @property
    def line_count(self) -> int:
        return len(self.line_starts)
