"""Open documents: their text and version, the analysis of that version, the latest analyses.

Checks run in the server's worker thread (``server/app.py``); what they find is recorded here on
the event loop's thread, so a document is only ever changed on that thread.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field

from rdcd_core.ide.analysis import Analysis
from rdcd_core.source import LineIndex, Span
from server.convert import Positions


@dataclass
class Document:
    uri: str
    version: int
    text: str
    analysis: Analysis | None = None  # of exactly ``text``
    last_good: Analysis | None = None  # the latest analysis without syntax errors
    newest: Analysis | None = None  # the analysis of the newest version checked so far
    newest_version: int | None = None
    published_version: int | None = None
    pending: asyncio.Task | None = None  # the debounced check
    checking: asyncio.Future | None = None  # the worker's analysis of ``checking_key``
    checking_key: tuple[int, str] | None = None  # (version, target)
    checking_text: str | None = None  # the text of ``checking_key``'s version
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

    def record(self, analysis: Analysis, version: int, text: str, target: str) -> None:
        """Keeps an analysis of ``text`` (version ``version``) for ``target``, made now or by the
        worker: as the current one only if the text and the target are still the document's."""
        if version == self.version and text is self.text and target == self.target and self.analysis is None:
            self.analysis = analysis
            analysis._line_index = self.line_index()
        if self.newest_version is None or version >= self.newest_version:
            self.newest, self.newest_version = analysis, version
            if analysis.model is not None and not analysis.has_syntax_errors:
                self.last_good = analysis

    def model_for_completion(self) -> Analysis | None:
        """The analysis completion reads, never waited for: the current one if good, else the
        last good one, else the newest (None before the first check has finished)."""
        if self.analysis is not None and not self.analysis.has_syntax_errors:
            return self.analysis
        return self.last_good or self.newest

    def stale(self) -> tuple[Analysis, Shift] | None:
        """The newest finished analysis, with the map of its text onto the current text, for
        answers that must not wait (hover). None when there is none yet."""
        if self.analysis is not None:
            return self.analysis, Shift(self.text, self.text)
        if self.newest is None:
            return None
        return self.newest, Shift(self.newest.text, self.text)

    def positions(self, encoding: str) -> Positions:
        if self._positions is None or self._positions.encoding != encoding:
            self._positions = Positions(self.line_index(), encoding)
        return self._positions


class Shift:
    """Maps offsets between an old text and a new one that share a prefix and a suffix (one
    edited region between them): places outside the edited region keep their meaning."""

    def __init__(self, old: str, new: str) -> None:
        self.old_length, self.new_length = len(old), len(new)
        limit = min(len(old), len(new))
        self.prefix = _common(limit, lambda k: old[:k] == new[:k])
        rest = limit - self.prefix
        self.suffix = _common(rest, lambda k: old[len(old) - k:] == new[len(new) - k:])

    def to_old(self, offset: int) -> int | None:
        """The offset in the old text of ``offset`` in the new one (None inside the edit)."""
        if offset <= self.prefix:
            return offset
        if offset >= self.new_length - self.suffix:
            return offset - self.new_length + self.old_length
        return None

    def to_new(self, span: Span) -> Span | None:
        """``span`` of the old text in the new one (None when it touches the edit)."""
        if span.end <= self.prefix:
            return span
        delta = self.new_length - self.old_length
        if span.start >= self.old_length - self.suffix:
            return Span(span.start + delta, span.end + delta)
        return None


def _common(limit: int, equal) -> int:  # type: ignore[no-untyped-def]
    """The largest k <= limit with equal(k), equal being monotone: a binary search of slice
    comparisons (each in C), not a Python loop over the characters."""
    low, high = 0, limit
    while low < high:
        middle = (low + high + 1) // 2
        if equal(middle):
            low = middle
        else:
            high = middle - 1
    return low


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
