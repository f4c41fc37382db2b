"""Text synchronisation and configuration: pygls applies the incremental edits; we re-check."""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from lsprotocol import types

if TYPE_CHECKING:
    from server.app import RdcdServer

log = logging.getLogger("rdcd.server")


def register(server: RdcdServer) -> None:
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
        try:
            text = ls.workspace.get_text_document(uri).source
        except Exception:
            log.exception("cannot read %s after a change", uri)
            return
        version = params.text_document.version
        document = ls.documents.get(uri)
        if document is None:
            ls.opened(uri, text, version)
            return
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
