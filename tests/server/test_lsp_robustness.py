"""The server never dies on bad input: unknown documents, positions past the end, malformed params."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from lsprotocol import types

from tests.server.conftest import ROOT, Session, doc


def alive(lsp: Session) -> None:
    uri = "file:///virtual/alive.rdcd"
    published = lsp.open(uri, "role A { }\ndeployment { A }\n")
    assert isinstance(published, list)


def test_unknown_document(lsp: Session) -> None:
    unknown = doc("file:///virtual/never-opened.rdcd")
    position = types.Position(line=0, character=0)
    hover = types.HoverParams(text_document=unknown, position=position)
    assert lsp.request(types.TEXT_DOCUMENT_HOVER, hover) is None
    assert not lsp.request(types.TEXT_DOCUMENT_DEFINITION,
                           types.DefinitionParams(text_document=unknown, position=position))
    symbols = types.DocumentSymbolParams(text_document=unknown)
    assert not lsp.request(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL, symbols)
    alive(lsp)


def test_positions_past_the_end(lsp: Session) -> None:
    uri = "file:///virtual/short.rdcd"
    lsp.open(uri, "role A { }\ndeployment { A }\n")
    far = types.Position(line=999, character=999)
    for method, params in [
        (types.TEXT_DOCUMENT_HOVER, types.HoverParams(text_document=doc(uri), position=far)),
        (types.TEXT_DOCUMENT_COMPLETION, types.CompletionParams(text_document=doc(uri), position=far)),
        (types.TEXT_DOCUMENT_SIGNATURE_HELP, types.SignatureHelpParams(text_document=doc(uri), position=far)),
        (types.TEXT_DOCUMENT_REFERENCES, types.ReferenceParams(
            text_document=doc(uri), position=far, context=types.ReferenceContext(include_declaration=True))),
    ]:
        lsp.request(method, params)
    alive(lsp)


def test_malformed_params_get_an_error() -> None:
    """Raw JSON-RPC (a real client cannot even send these): errors come back, the server stays up."""
    process = subprocess.Popen([sys.executable, "-m", "server", "--log-level", "ERROR"], cwd=str(ROOT),
                               stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    try:
        send(process, {"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}})
        assert receive(process, 1)["result"]["capabilities"]
        send(process, {"jsonrpc": "2.0", "method": "initialized", "params": {}})
        send(process, {"jsonrpc": "2.0", "id": 2, "method": "textDocument/hover", "params": {"nonsense": 1}})
        assert "error" in receive(process, 2)
        send(process, {"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {"textDocument": 3}})
        send(process, {"jsonrpc": "2.0", "id": 3, "method": "textDocument/definition",
                       "params": {"textDocument": {"uri": "file:///x.rdcd"}, "position": {"line": -5}}})
        assert "error" in receive(process, 3)
        send(process, {"jsonrpc": "2.0", "id": 4, "method": "workspace/symbol", "params": {"query": ""}})
        assert receive(process, 4)["result"] == []
        send(process, {"jsonrpc": "2.0", "id": 5, "method": "shutdown"})
        receive(process, 5)
        send(process, {"jsonrpc": "2.0", "method": "exit"})
        assert process.wait(timeout=10) == 0
    finally:
        if process.poll() is None:
            process.kill()


def send(process: subprocess.Popen, message: dict) -> None:
    body = json.dumps(message).encode()
    assert process.stdin is not None
    process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    process.stdin.flush()


def receive(process: subprocess.Popen, message_id: int) -> dict:
    """The response with ``message_id`` (notifications on the way are skipped)."""
    assert process.stdout is not None
    while True:
        length = 0
        while (header := process.stdout.readline()) not in (b"\r\n", b""):
            if header.lower().startswith(b"content-length:"):
                length = int(header.split(b":")[1])
        if not length:
            raise AssertionError("the server closed its output")
        message = json.loads(process.stdout.read(length))
        if message.get("id") == message_id:
            return message


def test_rename_in_empty_space_is_refused(lsp: Session) -> None:
    uri = "file:///virtual/space.rdcd"
    lsp.open(uri, "role A { }\n\n\ndeployment { A }\n")
    at = types.Position(line=1, character=0)
    assert lsp.request(types.TEXT_DOCUMENT_PREPARE_RENAME,
                       types.PrepareRenameParams(text_document=doc(uri), position=at)) is None
    with pytest.raises(Exception):  # noqa: B017
        lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(text_document=doc(uri), position=at,
                                                                   new_name="B"))
    alive(lsp)


def test_garbage_text_and_close(lsp: Session) -> None:
    uri = "file:///virtual/garbage.rdcd"
    published = lsp.open(uri, "}}}{{ role role ( ; := 99999999999 /* \x00 é 😀")
    assert published
    lsp.request(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, types.SemanticTokensParams(text_document=doc(uri)))
    lsp.request(types.TEXT_DOCUMENT_FOLDING_RANGE, types.FoldingRangeParams(text_document=doc(uri)))
    lsp.close_document(uri)
    alive(lsp)
