"""Acceptance: random byte streams — valid frames, cut frames, huge and wrong lengths, bad headers, noise,
JSON that is no message — sent to the real server over stdio; afterwards it is still running and
answers a valid request. One server serves every example (hypothesis's "ci" profile runs 200)."""

from __future__ import annotations

import itertools
import json
from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.server.rawclient import RawServer, frame, request

_ids = itertools.count(1)
URI = "file:///virtual/property.rdcd"

# never shutdown or exit (they end the session by design), never rdcd.simulate (a child process)
METHODS = ["textDocument/hover", "textDocument/completion", "textDocument/documentSymbol",
           "workspace/symbol", "textDocument/definition", "textDocument/didChange", "textDocument/didOpen",
           "textDocument/didClose", "$/cancelRequest", "workspace/executeCommand", "textDocument/formatting",
           "initialize", "workspace/didChangeConfiguration", "rdcd/unknown", "$/unknown"]

json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(max_size=30),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=10), inner, max_size=3),
    max_leaves=8)
params = st.one_of(
    json_values,
    st.fixed_dictionaries({"textDocument": st.fixed_dictionaries({"uri": st.just(URI)}),
                           "position": st.fixed_dictionaries({"line": st.integers(-3, 5),
                                                              "character": st.integers(-3, 50)})}),
    st.fixed_dictionaries({"command": st.sampled_from(["rdcd.showBytecode", "nope"]),
                           "arguments": st.lists(json_values, max_size=2)}),
)
messages = st.builds(
    lambda method, msg_id, value, with_id: {"jsonrpc": "2.0", "method": method, "params": value,
                                            **({"id": msg_id} if with_id else {})},
    st.sampled_from(METHODS), json_values, params, st.booleans())


def _cut(data: bytes, fraction: float) -> bytes:
    return data[: int(len(data) * fraction)]


pieces = st.one_of(
    messages.map(lambda m: frame(json.dumps(m).encode())),  # valid frames
    st.builds(lambda m, f: _cut(frame(json.dumps(m).encode()), f), messages, st.floats(0, 1)),  # cut frames
    st.builds(lambda m, delta: b"Content-Length: %d\r\n\r\n" % max(0, len(json.dumps(m)) + delta)
              + json.dumps(m).encode(), messages, st.integers(-20, 200)),  # wrong lengths
    st.sampled_from([10**12, 2**63, 2**64, 10**40]).map(lambda n: b"Content-Length: %d\r\n\r\n{}" % n),
    st.sampled_from([b"Content-Length: abc\r\n", b"Content-Length: -1\r\n\r\n", b"Content-Length 5\r\n",
                     b"\r\n", b"\n\n", b"Content-Type: x\r\n", b"X-Y: z\r\n" * 40, b"Content-Len",
                     b"Content-Length: 3\n\n", b"\x00" * 10, b"\xff\xfe\r\n"]),  # bad headers
    json_values.map(lambda v: frame(json.dumps(v).encode())),  # JSON that is no message
    st.binary(max_size=200).map(frame),  # frames of noise
    st.binary(max_size=200),  # plain noise
    messages.map(lambda m: frame(json.dumps(m).encode(), newline=b"\n")),  # LF-only
)


@pytest.fixture(scope="module")
def server() -> Iterator[RawServer]:
    raw = RawServer(log_level="ERROR")
    raw.initialize()
    yield raw
    try:
        assert raw.stop() == 0
        assert "Traceback" not in raw.stderr_text()
    finally:
        raw.kill()


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow], deadline=None)
@given(st.lists(pieces, min_size=1, max_size=8))
def test_server_survives_any_byte_stream(server: RawServer, stream: list[bytes]) -> None:
    server.send(b"".join(stream))
    msg_id = f"alive-{next(_ids)}"
    server.send(request(msg_id, "workspace/symbol", {"query": "no-such-symbol-anywhere"}))
    assert server.answer(msg_id, timeout=60)["result"] == []
    assert server.process.poll() is None
    assert not server.problems, server.problems
    server.received.clear()
