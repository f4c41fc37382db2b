"""Text synchronisation and configuration.

The server applies the editor's changes itself, on lines as the LSP defines them (``\\n``,
``\\r\\n``, ``\\r``: ``rdcd_core.source``). pygls's workspace documents split lines with
``str.splitlines``, which also breaks at form feed, U+2028 and others: after an edit below such a
character their text is no longer the editor's, and formatting it would rewrite the user's code.
So pygls's own didOpen/didChange/didClose handlers are taken out and these take their place.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from typing import TYPE_CHECKING

from lsprotocol import types

from rdcd_core.source import LineIndex
from server.convert import Positions

if TYPE_CHECKING:
    from server.app import RdcdServer

log = logging.getLogger("rdcd.server")

Change = types.TextDocumentContentChangePartial | types.TextDocumentContentChangeWholeDocument
_SYNC = (types.TEXT_DOCUMENT_DID_OPEN, types.TEXT_DOCUMENT_DID_CHANGE, types.TEXT_DOCUMENT_DID_CLOSE)


def apply_change(text: str, change: Change, encoding: str = "utf-16",
                 positions: Positions | None = None) -> str:
    """``text`` after one content change; its range is read in the negotiated position encoding
    (``positions``, if given, are those of ``text`` in it).

    Positions past the end of a line mean its end, lines past the last one the end of the text
    (as the LSP says); a range given backwards is taken forwards."""
    range_ = getattr(change, "range", None)
    if range_ is None:
        return change.text
    if positions is None or positions.index.text is not text or positions.encoding != encoding:
        positions = Positions(LineIndex(text), encoding)
    span = positions.span(range_)
    return text[:span.start] + change.text + text[span.end:]


def apply_changes(text: str, changes: Iterable[Change], encoding: str = "utf-16",
                  positions: Positions | None = None) -> str:
    """``text`` after the changes of one didChange, each on the text the one before left
    (``positions`` as for ``apply_change``: a line index of ``text`` already built is reused)."""
    for change in changes:
        text = apply_change(text, change, encoding, positions)
    return text


def register(server: RdcdServer) -> None:
    builtin = server.protocol.fm.builtin_features
    for method in _SYNC:  # pygls's handlers would keep a second, drifting copy of every document
        builtin.pop(method, None)

    @server.feature(types.INITIALIZE)
    def initialize(ls: RdcdServer, params: types.InitializeParams) -> None:
        ls.settings.update(params.initialization_options)
        ls.documents.retarget(ls.settings.target)

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: RdcdServer, params: types.DidOpenTextDocumentParams) -> None:
        item = params.text_document
        ls.opened(item.uri, item.text, item.version)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: RdcdServer, params: types.DidChangeTextDocumentParams) -> None:
        uri = params.text_document.uri
        version = params.text_document.version
        changes = list(params.content_changes)
        document = ls.documents.get(uri)
        if document is None:
            # Only a change that replaces the whole text says what a document never opened holds.
            whole = [i for i, change in enumerate(changes) if getattr(change, "range", None) is None]
            if not whole:
                log.warning("change to a document that is not open, ignored: %s", uri)
                return
            ls.opened(uri, apply_changes("", changes[whole[-1]:], ls.encoding), version)
            return
        text = apply_changes(document.text, changes, ls.encoding, ls.positions(document))
        document.update(text, version)
        ls.changed(document)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: RdcdServer, params: types.DidCloseTextDocumentParams) -> None:
        ls.closed(params.text_document.uri)

    @server.feature(types.WORKSPACE_DID_CHANGE_CONFIGURATION)
    def did_change_configuration(ls: RdcdServer, params: types.DidChangeConfigurationParams) -> None:
        before = ls.settings.fragment_size_hints
        ls.settings.update(params.settings)
        for document in ls.documents.retarget(ls.settings.target):  # check them for the new target
            ls.changed(document)
        if before != ls.settings.fragment_size_hints:
            try:
                ls.workspace_inlay_hint_refresh(None)
            except Exception:
                log.info("client cannot refresh inlay hints")
