"""The LSP life cycle through the real server over stdio: nothing before initialize, nothing after
shutdown, exit statuses; error answers carry no traceback and refusals are not logged as one."""

from __future__ import annotations

import pytest

from tests.server.rawclient import RawServer, frame, notification, request

URI = "file:///virtual/lifecycle.rdcd"
OPEN = {"textDocument": {"uri": URI, "languageId": "rdcd", "version": 1,
                         "text": "role A { }\ndeployment { A }\n"}}


@pytest.fixture
def server() -> RawServer:
    raw = RawServer()
    yield raw
    raw.kill()
    assert not raw.problems, raw.problems
    assert "Traceback" not in raw.stderr_text()


def test_requests_before_initialize_get_server_not_initialized(server: RawServer) -> None:
    server.send(request(1, "textDocument/hover", {"textDocument": {"uri": URI},
                                                  "position": {"line": 0, "character": 0}}))
    server.send(request(2, "shutdown"))
    server.send(request(3, "rdcd/noSuchMethod", {}))
    for msg_id in (1, 2, 3):
        assert server.answer(msg_id)["error"]["code"] == -32002
    server.initialize()
    server.send(request(4, "workspace/symbol", {"query": ""}))
    assert server.answer(4)["result"] == []
    assert server.stop() == 0


def test_notifications_before_initialize_are_dropped(server: RawServer) -> None:
    server.send(notification("textDocument/didOpen", OPEN))
    server.initialize()
    server.send(request("symbols", "textDocument/documentSymbol", {"textDocument": {"uri": URI}}))
    assert not server.answer("symbols").get("result")  # the document was never opened
    assert not any(m.get("method") == "textDocument/publishDiagnostics" for m in server.received)
    assert server.stop() == 0


def test_initialize_twice_is_refused(server: RawServer) -> None:
    server.initialize()
    server.send(request("again", "initialize", {"processId": None, "rootUri": None, "capabilities": {}}))
    assert server.answer("again")["error"]["code"] == -32600
    assert server.stop() == 0


def test_requests_after_shutdown_get_invalid_request(server: RawServer) -> None:
    server.initialize()
    server.send(request("down", "shutdown"))
    assert server.answer("down")["result"] is None
    server.send(request("late", "workspace/symbol", {"query": ""}))
    server.send(request("late-2", "shutdown"))
    server.send(notification("textDocument/didOpen", OPEN))
    assert server.answer("late")["error"]["code"] == -32600
    assert server.answer("late-2")["error"]["code"] == -32600
    server.send(notification("exit"))
    assert server.wait() == 0
    assert not any(m.get("method") == "textDocument/publishDiagnostics" for m in server.received)


def test_exit_without_shutdown_exits_with_1(server: RawServer) -> None:
    server.initialize()
    server.send(notification("exit"))
    assert server.wait() == 1


def test_exit_before_initialize_exits_with_1(server: RawServer) -> None:
    server.send(notification("exit"))
    assert server.wait() == 1


def test_end_of_input_without_shutdown_exits_with_1(server: RawServer) -> None:
    server.initialize()
    assert server.process.stdin is not None
    server.process.stdin.close()
    assert server.wait() == 1


def test_end_of_input_after_shutdown_exits_with_0(server: RawServer) -> None:
    server.initialize()
    server.send(request("down", "shutdown"))
    server.answer("down")
    assert server.process.stdin is not None
    server.process.stdin.close()
    assert server.wait() == 0


def test_end_of_input_inside_a_frame(server: RawServer) -> None:
    server.initialize()
    server.send(b"Content-Length: 100\r\n\r\n{\"jsonrpc\"")
    assert server.process.stdin is not None
    server.process.stdin.close()
    assert server.wait() == 1


def test_refusals_are_one_line_answers_and_not_logged_as_tracebacks(server: RawServer) -> None:
    """RequestFailed (a refused rename, a simulation of errors), invalid params, unknown commands."""
    server.initialize()
    text = "role A { }\n\n\ndeployment { A }\n"
    server.send(notification("textDocument/didOpen", {"textDocument": {
        "uri": URI, "languageId": "rdcd", "version": 1, "text": text}}))
    server.published(URI)
    server.send(request("rename", "textDocument/rename", {
        "textDocument": {"uri": URI}, "position": {"line": 1, "character": 0}, "newName": "B"}))
    server.send(request("command", "workspace/executeCommand", {"command": "rdcd.noSuchCommand"}))
    server.send(request("bytecode", "workspace/executeCommand", {"command": "rdcd.showBytecode",
                                                                  "arguments": [42]}))
    server.send(request("params", "textDocument/definition", {"textDocument": {"uri": URI},
                                                              "position": {"line": -5}}))
    for msg_id in ("rename", "command", "bytecode", "params"):
        error = server.answer(msg_id)["error"]
        assert error["message"] and "data" not in error, error
    assert server.stop() == 0
    assert "Traceback" not in server.stderr_text()


def test_cancel_request_for_unknown_id_is_harmless(server: RawServer) -> None:
    server.initialize()
    server.send(notification("$/cancelRequest", {"id": "nothing"}))
    server.send(frame({"jsonrpc": "2.0", "method": "$/cancelRequest", "params": {}}))
    server.send(request("after", "workspace/symbol", {"query": ""}))
    assert server.answer("after")["result"] == []
    assert server.stop() == 0


def test_an_uncollected_refusal_at_the_end_is_one_line(caplog: pytest.LogCaptureFixture) -> None:
    """The server can end while pygls passes a cancelled simulation's refusal between its futures;
    asyncio then reports it as never retrieved: one line, no traceback. Other errors as asyncio does."""
    import asyncio
    import logging

    from pygls.exceptions import JsonRpcRequestCancelled

    from server.stdio import _unretrieved

    loop = asyncio.new_event_loop()
    try:
        error = JsonRpcRequestCancelled("simulation cancelled")
        error.__traceback__ = None
        with caplog.at_level(logging.INFO):
            message = "Task exception was never retrieved"
            _unretrieved(loop, {"message": message, "exception": error})
            _unretrieved(loop, {"message": message, "exception": ValueError("real")})
    finally:
        loop.close()
    lines = [r.getMessage() for r in caplog.records]
    assert "at the end: Task exception was never retrieved (simulation cancelled)" in lines
    real = [r for r in caplog.records if r.exc_info and isinstance(r.exc_info[1], ValueError)]
    assert real and real[0].name == "asyncio"  # asyncio's own report, with the traceback
