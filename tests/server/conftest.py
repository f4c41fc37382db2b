"""One real ``rdcd-lsp`` (``python -m server``) over stdio for all server tests, driven by the
pytest-lsp client from a private event loop so that plain and hypothesis tests can share it."""

from __future__ import annotations

import asyncio
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from lsprotocol import types
from pygls.protocol import default_converter
from pytest_lsp import LanguageClient
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def _record(client: LanguageClient, params: types.PublishDiagnosticsParams) -> None:
    client.diagnostics[params.uri] = params.diagnostics
    client.published.setdefault(params.uri, []).append(params)


def make_client() -> LanguageClient:
    client = LanguageClient(converter_factory=default_converter)
    features = dict(DEFAULT_CLIENT_FEATURES)
    features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = _record
    register_lsp_features(client, features)
    client.published = {}  # type: ignore[attr-defined]
    return client


class Session:
    """A started server and a client; ``run`` drives a coroutine on the session's loop."""

    def __init__(self, init_options: Any = None, debounce_ms: float = 10,
                 root_uri: str | None = None) -> None:
        self.loop = asyncio.new_event_loop()
        self.client = make_client()
        self.versions: dict[str, int] = {}
        command = [sys.executable, "-m", "server", "--debounce-ms", str(debounce_ms), "--log-level", "ERROR"]
        self.run(self.client.start_io(*command, cwd=str(ROOT)))
        capabilities = types.ClientCapabilities(
            window=types.WindowClientCapabilities(work_done_progress=True),
            text_document=types.TextDocumentClientCapabilities(
                hover=types.HoverClientCapabilities(content_format=[types.MarkupKind.Markdown]),
                completion=types.CompletionClientCapabilities(
                    completion_item=types.ClientCompletionItemOptions(snippet_support=True)),
                publish_diagnostics=types.PublishDiagnosticsClientCapabilities(version_support=True),
            ),
        )
        params = types.InitializeParams(capabilities=capabilities, initialization_options=init_options,
                                        root_uri=root_uri)
        self.initialize_result = self.run(self.client.initialize_session(params))

    def run(self, coroutine: Any, timeout: float = 30) -> Any:
        return self.loop.run_until_complete(asyncio.wait_for(coroutine, timeout))

    def close(self) -> None:
        try:
            self.run(self.client.shutdown_session(), timeout=10)
        finally:
            self.loop.close()

    # -- documents -----------------------------------------------------------------------------
    def open(self, uri: str, text: str) -> list[types.Diagnostic]:
        self.versions[uri] = 1
        self.client.text_document_did_open(types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="rdcd", version=1, text=text)))
        return self.diagnostics(uri, 1)

    def change(self, uri: str, changes: list[Any], wait: bool = True) -> list[types.Diagnostic] | None:
        self.versions[uri] += 1
        version = self.versions[uri]
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=changes))
        return self.diagnostics(uri, version) if wait else None

    def replace_all(self, uri: str, text: str) -> list[types.Diagnostic] | None:
        return self.change(uri, [types.TextDocumentContentChangeWholeDocument(text=text)])

    def diagnostics(self, uri: str, version: int, timeout: float = 20) -> list[types.Diagnostic]:
        async def wait() -> list[types.Diagnostic]:
            deadline = time.monotonic() + timeout
            while time.monotonic() < deadline:
                for params in reversed(self.client.published.get(uri, [])):  # type: ignore[attr-defined]
                    if params.version == version:
                        return list(params.diagnostics)
                await asyncio.sleep(0.005)
            raise TimeoutError(f"no diagnostics for {uri} version {version}")

        return self.run(wait(), timeout + 5)

    def close_document(self, uri: str) -> None:
        self.client.text_document_did_close(types.DidCloseTextDocumentParams(
            text_document=types.TextDocumentIdentifier(uri=uri)))

    # -- requests ------------------------------------------------------------------------------
    def request(self, method: str, params: Any) -> Any:
        return self.run(self.client.protocol.send_request_async(method, params))


@pytest.fixture(scope="session")
def lsp() -> Iterator[Session]:
    session = Session()
    yield session
    session.close()


def offset_of(text: str, needle: str, nth: int = 0, delta: int = 0) -> int:
    """The offset of the ``nth`` occurrence of ``needle`` (plus ``delta`` characters)."""
    index = -1
    for _ in range(nth + 1):
        index = text.index(needle, index + 1)
    return index + delta


def position_of(text: str, needle: str, nth: int = 0, delta: int = 0) -> types.Position:
    """The LSP position of the ``nth`` occurrence of ``needle`` (plus ``delta`` characters)."""
    index = offset_of(text, needle, nth, delta)
    line = text.count("\n", 0, index)
    column = index - (text.rfind("\n", 0, index) + 1)
    return types.Position(line=line, character=column)


def doc(uri: str) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri=uri)
