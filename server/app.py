"""The RDCD language server: document sync, debounced checking and diagnostics publishing.

Language features live in ``server/features.py`` and ``server/views.py``, commands in
``server/commands.py``; all of them only map ``rdcd_core.ide`` functions to LSP.
"""

from __future__ import annotations

import asyncio
import logging
import time
from typing import Any

from lsprotocol import types
from pygls.lsp.server import LanguageServer

from rdcd_core import __version__
from rdcd_core.ide.analysis import Analysis
from server.config import Settings
from server.convert import Positions
from server.documents import Document, Documents
from server.lsp_diagnostics import to_lsp_diagnostics
from server.protocol import RdcdProtocol

log = logging.getLogger("rdcd.server")


class RdcdServer(LanguageServer):
    def __init__(self, settings: Settings | None = None) -> None:
        super().__init__("rdcd-lsp", __version__,
                         text_document_sync_kind=types.TextDocumentSyncKind.Incremental,
                         protocol_cls=RdcdProtocol)
        self.documents = Documents()
        self.settings = settings or Settings()

    def report_server_error(self, error: Exception, source: Any) -> None:
        """Bad input is logged, not shown to the user in a message box."""
        log.error("%s: %s", getattr(source, "__name__", source), error)

    @property
    def encoding(self) -> str:
        try:
            encoding = self.workspace.position_encoding
        except Exception:
            encoding = None
        return str(getattr(encoding, "value", encoding) or "utf-16")

    # -- access for features ----------------------------------------------------------------
    def document(self, uri: str) -> Document | None:
        document = self.documents.get(uri)
        if document is None:
            log.info("request for a document that is not open: %s", uri)
        return document

    def positions(self, document: Document) -> Positions:
        return document.positions(self.encoding)

    # -- sync ---------------------------------------------------------------------------------
    def opened(self, uri: str, text: str, version: int) -> None:
        self.changed(self.documents.put(uri, text, version))

    def changed(self, document: Document) -> None:
        if document.pending is not None:
            document.pending.cancel()
        task = self._check_later(document, document.version)
        document.pending = asyncio.get_running_loop().create_task(task)

    def closed(self, uri: str) -> None:
        document = self.documents.close(uri)
        if document is not None and document.pending is not None:
            document.pending.cancel()
        self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))

    async def _check_later(self, document: Document, version: int) -> None:
        try:
            await asyncio.sleep(self.settings.debounce_ms / 1000)
            if document.version != version or self.documents.get(document.uri) is not document:
                return  # a newer change is on its way
            started = time.perf_counter()
            analysis = document.current()
            checked = time.perf_counter()
            self.publish(document, analysis, version)
            log.debug("%s v%d: checked in %.1f ms, published in %.1f ms", document.uri, version,
                      (checked - started) * 1000, (time.perf_counter() - checked) * 1000)
        except asyncio.CancelledError:
            pass
        except Exception:
            log.exception("checking %s failed", document.uri)

    def publish(self, document: Document, analysis: Analysis, version: int) -> None:
        """Publishes unless a newer version was already published or the text moved on."""
        if document.version != version:
            return
        if document.published_version is not None and document.published_version > version:
            return
        document.published_version = version
        diagnostics = to_lsp_diagnostics(analysis.diagnostics, self.positions(document), document.uri)
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=document.uri, diagnostics=diagnostics, version=version))


def create_server(settings: Settings | None = None) -> RdcdServer:
    server = RdcdServer(settings)
    from server import commands, features, sync, views

    sync.register(server)
    features.register(server)
    views.register(server)
    commands.register(server)
    return server
