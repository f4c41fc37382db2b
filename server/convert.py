"""Offsets (code points) ↔ LSP positions in the negotiated encoding (UTF-16 by default).

The only place that knows about UTF-16 (docs/architecture.md rule 3).
"""

from __future__ import annotations

from lsprotocol import types

from rdcd_core.source import LineIndex, Span


def _units(text: str, encoding: str) -> int:
    if text.isascii():
        return len(text)
    if encoding == "utf-8":
        return len(text.encode("utf-8"))
    if encoding == "utf-32":
        return len(text)
    return sum(2 if ord(char) > 0xFFFF else 1 for char in text)


class Positions:
    def __init__(self, index: LineIndex, encoding: str = "utf-16") -> None:
        self.index = index
        self.encoding = encoding

    def position(self, offset: int) -> types.Position:
        line_col = self.index.line_col(offset)
        prefix = self.index.line_text(line_col.line)[: line_col.column]
        return types.Position(line=line_col.line, character=_units(prefix, self.encoding))

    def range(self, span: Span) -> types.Range:
        return types.Range(start=self.position(span.start), end=self.position(span.end))

    def offset(self, position: types.Position) -> int:
        """The offset of a client position, clamped into the text (positions past the end are fine)."""
        line = max(0, position.line)
        if line >= self.index.line_count:
            return len(self.index.text)
        text = self.index.line_text(line)
        units = max(0, position.character)
        if text.isascii() or self.encoding == "utf-32":
            column = min(units, len(text))
        else:
            column = 0
            consumed = 0
            while column < len(text) and consumed < units:
                consumed += _units(text[column], self.encoding)
                column += 1
        return self.index.offset(line, column)

    def span(self, range_: types.Range) -> Span:
        start, end = self.offset(range_.start), self.offset(range_.end)
        return Span(min(start, end), max(start, end))
