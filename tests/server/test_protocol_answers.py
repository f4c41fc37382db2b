"""How the protocol answers a handler's outcome: a bug becomes a one-line InternalError (its traceback
in the log only), a refusal the handler meant is answered and logged on one line."""

from __future__ import annotations

import json
import logging
from concurrent.futures import Future

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcInternalError

from server.app import create_server
from server.guard import RequestFailed


class Capture:
    def __init__(self) -> None:
        self.frames: list[bytes] = []

    def write(self, data: bytes) -> None:
        self.frames.append(data)

    def messages(self) -> list[dict]:
        return [json.loads(data.split(b"\r\n\r\n", 1)[1]) for data in self.frames]


@pytest.fixture
def protocol():  # noqa: ANN201
    server = create_server()
    capture = Capture()
    server.protocol.set_writer(capture)
    server.protocol.capture = capture
    return server.protocol


def finished(error: BaseException | None = None, result: object = None) -> Future:
    future: Future = Future()
    if error is None:
        future.set_result(result)
    else:
        future.set_exception(error)
    return future


def test_a_bug_is_answered_without_its_traceback(protocol, caplog: pytest.LogCaptureFixture) -> None:
    try:
        {}["missing"]
    except KeyError as error:
        bug = error
    with caplog.at_level(logging.INFO, logger="rdcd.server"):
        protocol._send_handler_result(finished(bug), msg_id=7)
    [answer] = protocol.capture.messages()
    assert answer["id"] == 7 and answer["error"]["code"] == -32603
    assert "data" not in answer["error"] and "\n" not in answer["error"]["message"]
    assert any(record.exc_info for record in caplog.records)  # the developer still finds it in the log


def test_a_refusal_is_answered_and_logged_on_one_line(protocol, caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.DEBUG):
        protocol._send_handler_result(finished(RequestFailed("nothing to rename here")), msg_id="r")
    [answer] = protocol.capture.messages()
    error = {"code": -32803, "message": "nothing to rename here"}
    assert answer == {"jsonrpc": "2.0", "id": "r", "error": error}
    assert not any(record.exc_info for record in caplog.records)
    assert not any("Traceback" in record.getMessage() for record in caplog.records)


def test_traceback_data_of_pygls_errors_is_dropped(protocol) -> None:
    try:
        raise ValueError("boom")
    except ValueError:
        import sys

        error = JsonRpcInternalError.of(sys.exc_info())
    assert error.data and "traceback" in error.data
    protocol._send_response(3, error=error.to_response_error())
    [answer] = protocol.capture.messages()
    assert "data" not in answer["error"]


def test_a_cancelled_request_is_answered(protocol) -> None:
    future: Future = Future()
    future.cancel()
    protocol._send_handler_result(future, msg_id=9)
    [answer] = protocol.capture.messages()
    assert answer["error"]["code"] == -32800


def test_results_are_answered(protocol) -> None:
    protocol._send_handler_result(finished(result=[types.Location(
        uri="file:///a", range=types.Range(start=types.Position(line=0, character=0),
                                           end=types.Position(line=0, character=1)))]), msg_id=1)
    [answer] = protocol.capture.messages()
    assert answer["result"][0]["uri"] == "file:///a"
