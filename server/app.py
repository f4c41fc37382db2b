"""The RDCD language server: document sync, debounced checking and diagnostics publishing.

Language features live in ``server/features.py`` and ``server/views.py``, commands in
``server/commands.py``; all of them only map ``rdcd_core.ide`` functions to LSP.
"""

from __future__ import annotations

import asyncio
import functools
import logging
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from lsprotocol import types
from pygls.lsp.server import LanguageServer

from rdcd_core import __version__
from rdcd_core.ide.analysis import Analysis, analyze
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
        # Checks run here, one at a time, so that a long one never holds up the event loop.
        self.checker = ThreadPoolExecutor(max_workers=1, thread_name_prefix="rdcd-check")

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
            analysis = await self.analysis_of(document)
            if analysis is None:
                return  # the text moved on meanwhile; its own check publishes
            checked = time.perf_counter()
            self.publish(document, analysis, version)
            log.debug("%s v%d: checked in %.1f ms, published in %.1f ms", document.uri, version,
                      (checked - started) * 1000, (time.perf_counter() - checked) * 1000)
        except asyncio.CancelledError:
            pass
        except Exception:
            log.exception("checking %s failed", document.uri)

    async def checked(self, uri: str) -> tuple[Document, Analysis] | None:
        """(document, analysis) of the document's text as it is now, waited for without holding up
        the loop; None for a document that is not open, or when the text changed meanwhile (the
        client asks again). For requests whose answer must match the text they were asked on."""
        document = self.document(uri)
        if document is None:
            return None
        text = document.text
        analysis = await self.analysis_of(document)
        if analysis is None or document.text is not text:
            return None
        return document, analysis

    async def analysis_of(self, document: Document) -> Analysis | None:
        """The analysis of the document's text as it is now, made in the worker thread while the
        event loop goes on answering; None if the text changed before it was ready. Every request
        waiting for the same version shares one check."""
        if document.analysis is not None:
            return document.analysis
        version, text, target = document.version, document.text, document.target
        if document.checking is None or document.checking_key != (version, target):
            previous = document.last_good
            future = asyncio.get_running_loop().run_in_executor(
                self.checker, self._analyze, document, version, text, previous, target)
            future.add_done_callback(functools.partial(self._checked, document, version, text, target))
            document.checking, document.checking_key, document.checking_text = future, (version, target), text
        (checked_version, checked_target), checked_text = document.checking_key, document.checking_text
        # shielded: a cancelled request (or debounce) must not cancel a check others wait for
        found = await asyncio.shield(document.checking)
        if found is not None:
            # a check that was already done returns here at once, maybe before its done callback
            # (``_checked``) has run: record it now (``record`` keeps the first, so twice is harmless)
            document.record(found, checked_version, checked_text, checked_target)
        return document.analysis if document.text is text else None

    @staticmethod
    def _analyze(document: Document, version: int, text: str, previous: Analysis | None,
                 target: str) -> Analysis | None:
        """Runs in the worker thread. A check queued behind others is skipped once its version
        (or target) is no longer the document's (reading an attribute is safe from this thread)."""
        if document.version != version or document.target != target:
            return None
        return analyze(text, previous=previous, target=target)

    @staticmethod
    def _checked(document: Document, version: int, text: str, target: str, future: asyncio.Future) -> None:
        """On the loop's thread: records what the worker found."""
        if document.checking is future:
            document.checking = document.checking_key = document.checking_text = None
        if future.cancelled():
            return
        if future.exception() is not None:
            log.error("checking %s failed: %s", document.uri, future.exception())
        elif future.result() is not None:
            document.record(future.result(), version, text, target)

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


# The check thread and the loop share the GIL: hand it over every millisecond (not every 5), so
# that a request arriving during a long check is answered within a few milliseconds.
SWITCH_INTERVAL = 0.001


def create_server(settings: Settings | None = None) -> RdcdServer:
    sys.setswitchinterval(SWITCH_INTERVAL)
    server = RdcdServer(settings)
    from server import commands, features, sync, views

    sync.register(server)
    features.register(server)
    views.register(server)
    commands.register(server)
    return server
