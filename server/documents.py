"""Open documents: their text and version, the analysis of that version, the last good analysis."""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field

from rdcd_core.ide.analysis import Analysis, analyze
from rdcd_core.source import LineIndex
from server.convert import Positions


@dataclass
class Document:
    uri: str
    version: int
    text: str
    analysis: Analysis | None = None  # of exactly ``text``
    last_good: Analysis | None = None  # the latest analysis without syntax errors
    published_version: int | None = None
    pending: asyncio.Task | None = None
    target: str = "default"  # the setting rdcd.target: what the program is checked for
    _positions: Positions | None = field(default=None, repr=False)
    _index: LineIndex | None = field(default=None, repr=False)

    def update(self, text: str, version: int) -> None:
        self.text = text
        self.version = version
        self.analysis = None
        self._positions = None

    def line_index(self) -> LineIndex:
        if self._index is None or self._index.text is not self.text:
            self._index = LineIndex(self.text)
        return self._index

    def current(self) -> Analysis:
        """The analysis of the current text (checked now if it has not been yet)."""
        if self.analysis is None:
            self.analysis = analyze(self.text, previous=self.last_good, target=self.target)
            self.analysis._line_index = self.line_index()
            if self.analysis.model is not None and not self.analysis.has_syntax_errors:
                self.last_good = self.analysis
        return self.analysis

    def model_for_completion(self) -> Analysis:
        """The analysis completion reads: the current one if good, else the last good one."""
        if self.analysis is not None and not self.analysis.has_syntax_errors:
            return self.analysis
        return self.last_good or self.current()

    def positions(self, encoding: str) -> Positions:
        if self._positions is None or self._positions.encoding != encoding:
            self._positions = Positions(self.line_index(), encoding)
        return self._positions


class Documents:
    def __init__(self) -> None:
        self.open: dict[str, Document] = {}
        self.target = "default"

    def retarget(self, target: str) -> list[Document]:
        """Checks every open document for ``target`` from now on; returns those to check again."""
        if target == self.target:
            return []
        self.target = target
        for document in self.open.values():
            document.target, document.analysis = target, None
        return list(self.open.values())

    def get(self, uri: str) -> Document | None:
        return self.open.get(uri)

    def put(self, uri: str, text: str, version: int) -> Document:
        document = self.open.get(uri)
        if document is None:
            document = self.open[uri] = Document(uri, version, text, target=self.target)
        else:
            document.update(text, version)
        return document

    def close(self, uri: str) -> Document | None:
        return self.open.pop(uri, None)
