"""Broken frames through the real server over stdio: it answers what it can, refuses the rest with an
error (id null), resynchronises on the next header and answers the next valid request."""

from __future__ import annotations

import itertools
import json
from collections.abc import Iterator

import pytest

from tests.server.rawclient import RawServer, frame, notification, request

_ids = itertools.count(1)


@pytest.fixture(scope="module")
def server() -> Iterator[RawServer]:
    raw = RawServer()
    raw.initialize()
    yield raw
    try:
        assert raw.stop() == 0
        assert not raw.problems, raw.problems
        assert "Traceback" not in raw.stderr_text()
    finally:
        raw.kill()


def answers(server: RawServer) -> list[dict]:
    """A valid request after the damage gets its answer; the errors (id null) sent before it."""
    msg_id = next(_ids)
    server.send(request(msg_id, "workspace/symbol", {"query": "nothing-matches-this"}))
    assert server.answer(msg_id)["result"] == []
    errors = [m for m in server.received if "error" in m and m.get("id") is None]
    server.received = [m for m in server.received if m not in errors]
    return errors


def null_error(server: RawServer, code: int) -> dict:
    message = server.next_message(lambda m: "error" in m and m.get("id") is None)
    assert message["error"]["code"] == code, message
    return message["error"]


HUGE = [10**12, 2**63, 2**63 - 1, 2**64 + 1, 10**20 - 1, 256 * 1024 * 1024 + 1]


@pytest.mark.parametrize("length", HUGE)
def test_huge_content_length_is_refused(server: RawServer, length: int) -> None:
    server.send(b"Content-Length: %d\r\n\r\n{\"jsonrpc\": \"2.0\", \"method\": \"x\"}" % length)
    assert str(length) in null_error(server, -32600)["message"]
    answers(server)


def test_a_huge_length_whose_bytes_follow_is_skipped(server: RawServer) -> None:
    """The limit is small here only in spirit: a body sent after a refused length is drained, not
    taken for headers, and the frame after it is read."""
    body = json.dumps({"jsonrpc": "2.0", "method": "x", "params": {"text": "a" * 300_000}}).encode()
    server.send(b"Content-Length: 999999999999\r\n\r\n" + body)
    null_error(server, -32600)
    answers(server)


GARBAGE = {
    "bad header line": b"hello world\r\n",
    "garbage without a line break": b"\x00\xff\xfe garbage",
    "body without header": json.dumps({"jsonrpc": "2.0", "id": "lost", "method": "shutdown"}).encode(),
    "non-numeric length": b"Content-Length: twelve\r\n\r\n{}",
    "negative length": b"Content-Length: -5\r\n\r\n{}",
    "length with sign": b"Content-Length: +5\r\n\r\n{}",
    "two lengths": b"Content-Length: 2\r\nContent-Length: 3\r\n\r\n",
    "no length": b"Content-Type: application/vscode-jsonrpc\r\n\r\n{}",
    "header line of a megabyte": b"X-Junk: " + b"j" * 1_000_000 + b"\r\n",
    "many headers": b"X-A: 1\r\n" * 100,
    "truncated frame": b"Content-Length: 40\r\n\r\n{\"jsonrpc\"",
    "truncated header": b"Content-Len",
    "length too short": frame(b'{"jsonrpc": "2.0", "id": "short", "method": "shutdown"}')[:-5],
    "binary noise": bytes(range(256)) * 4,
}


@pytest.mark.parametrize("garbage", GARBAGE.values(), ids=GARBAGE.keys())
def test_garbage_is_survived(server: RawServer, garbage: bytes) -> None:
    server.send(garbage)
    errors = answers(server)
    assert len(errors) == (2 if garbage.startswith(b"Content-Length: 2\r\n") else 1), errors
    assert all(error["error"]["code"] in (-32700, -32600) for error in errors)  # one per broken stretch


def test_lf_only_headers_are_read(server: RawServer) -> None:
    msg_id = next(_ids)
    server.send(frame({"jsonrpc": "2.0", "id": msg_id, "method": "workspace/symbol", "params": {"query": ""}},
                      newline=b"\n"))
    assert server.answer(msg_id)["result"] == []


def test_headers_in_any_case_with_content_type(server: RawServer) -> None:
    body = json.dumps({"jsonrpc": "2.0", "id": "case", "method": "workspace/symbol", "params": {"query": ""}})
    server.send(b"content-type: application/vscode-jsonrpc; charset=utf-8\r\n"
                b"CONTENT-LENGTH:%d  \r\n\r\n%s" % (len(body), body.encode()))
    assert server.answer("case")["result"] == []


def test_blank_lines_between_frames_are_harmless(server: RawServer) -> None:
    server.send(b"\r\n\r\n\n")
    assert answers(server) == []


def test_length_too_long_loses_no_request(server: RawServer) -> None:
    """The next frame began inside the claimed body: both requests are answered."""
    first = json.dumps({"jsonrpc": "2.0", "id": "long-1", "method": "workspace/symbol",
                        "params": {"query": ""}}).encode()
    server.send(b"Content-Length: %d\r\n\r\n" % (len(first) + 500) + first
                + request("long-2", "workspace/symbol", {"query": ""}))
    assert server.answer("long-1")["result"] == []
    assert server.answer("long-2")["result"] == []


def test_frame_split_into_single_bytes(server: RawServer) -> None:
    for byte in request("bytes", "workspace/symbol", {"query": ""}):
        server.send(bytes([byte]))
    assert server.answer("bytes")["result"] == []


def test_many_frames_in_one_write(server: RawServer) -> None:
    server.send(b"".join(request(f"many-{i}", "workspace/symbol", {"query": ""}) for i in range(50)))
    for i in range(50):
        assert server.answer(f"many-{i}")["result"] == []


# -- the JSON inside a frame ---------------------------------------------------------------------
MALFORMED_JSON = {
    "not json": b"{this is not json}",
    "empty body": b"",
    "truncated": b'{"jsonrpc": "2.0", "id": 1, "method": "initia',
    "invalid utf-8": b'{"jsonrpc": "2.0", "id": 1, "method": "\xff\xfe"}',
    "NaN is not JSON": b'{"jsonrpc": "2.0", "id": 1, "method": "x", "params": NaN}',
    "deep nesting": b"[" * 200_000 + b"]" * 200_000,
    "huge integer": b'{"jsonrpc": "2.0", "id": 1' + b"0" * 10_000 + b', "method": "x"}',
    "trailing data": b'{"jsonrpc": "2.0", "method": "x"} {}',
}


@pytest.mark.parametrize("body", MALFORMED_JSON.values(), ids=MALFORMED_JSON.keys())
def test_malformed_json_gets_parse_error(server: RawServer, body: bytes) -> None:
    server.send(frame(body))
    assert null_error(server, -32700)["message"].startswith("Parse error")
    answers(server)


NOT_MESSAGES = {
    "array (batch)": [{"jsonrpc": "2.0", "id": 1, "method": "shutdown"}],
    "number": 42,
    "string": "shutdown",
    "null": None,
    "no jsonrpc": {"id": "v", "method": "workspace/symbol", "params": {"query": ""}},
    "jsonrpc 1.0": {"jsonrpc": "1.0", "method": "x"},
    "object id": {"jsonrpc": "2.0", "id": {"a": 1}, "method": "workspace/symbol", "params": {"query": ""}},
    "boolean id": {"jsonrpc": "2.0", "id": True, "method": "workspace/symbol", "params": {"query": ""}},
    "float id": {"jsonrpc": "2.0", "id": 1.5, "method": "workspace/symbol", "params": {"query": ""}},
}


@pytest.mark.parametrize("message", NOT_MESSAGES.values(), ids=NOT_MESSAGES.keys())
def test_not_a_message_gets_invalid_request(server: RawServer, message: object) -> None:
    """Answered with the message's id when it has a usable one, else with id null."""
    server.send(frame(json.dumps(message).encode()))
    if isinstance(message, dict) and message.get("id") == "v":
        assert server.answer("v")["error"]["code"] == -32600
    else:
        null_error(server, -32600)
    answers(server)


def test_method_of_the_wrong_type(server: RawServer) -> None:
    server.send(frame({"jsonrpc": "2.0", "id": "m", "method": 7}))
    assert server.answer("m")["error"]["code"] == -32600


def test_unknown_method(server: RawServer) -> None:
    server.send(request("unknown", "rdcd/noSuchMethod", {}))
    assert server.answer("unknown")["error"]["code"] == -32601
    server.send(notification("rdcd/noSuchNotification", {}))
    answers(server)


def test_invalid_params_are_answered(server: RawServer) -> None:
    server.send(request("params", "textDocument/hover", {"nonsense": 1}))
    error = server.answer("params")["error"]
    assert error["code"] == -32602
    assert "textDocument" in error["message"]


def test_notification_sent_as_request(server: RawServer) -> None:
    server.send(request("as-request", "textDocument/didClose", {"textDocument": {"uri": "file:///x.rdcd"}}))
    assert server.answer("as-request")["error"]["code"] == -32600


def test_answers_to_requests_never_asked(server: RawServer) -> None:
    server.send(frame({"jsonrpc": "2.0", "id": "never-asked", "result": {"x": 1}}))
    server.send(frame({"jsonrpc": "2.0", "id": "never-asked-2", "error": {"code": 1, "message": "m"}}))
    server.send(frame({"jsonrpc": "2.0", "result": 1}))
    answers(server)
