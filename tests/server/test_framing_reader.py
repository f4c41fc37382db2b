"""``server/framing.py`` on its own: valid streams cut anywhere give exactly their bodies, and after
any bytes at all the next valid frame is read."""

from __future__ import annotations

import json

from hypothesis import given
from hypothesis import strategies as st

from server.framing import MAX_HEADER_LINE, Body, FrameReader, Problem


def frame(body: bytes, newline: bytes = b"\r\n") -> bytes:
    return b"Content-Length: %d" % len(body) + newline + newline + body


def feed_in_pieces(reader: FrameReader, data: bytes, cuts: list[int]) -> list[Body | Problem]:
    found: list[Body | Problem] = []
    start = 0
    for cut in sorted(set(cuts)) + [len(data)]:
        found += reader.feed(data[start:cut])
        start = max(start, cut)
    return found


bodies = st.builds(
    lambda text, ascii_only: json.dumps({"jsonrpc": "2.0", "method": "m", "params": {"text": text}},
                                        ensure_ascii=ascii_only).encode("utf-8", "surrogatepass"),
    st.text(max_size=200), st.booleans())


@given(st.lists(bodies, min_size=1, max_size=6), st.lists(st.integers(0, 4000), max_size=12), st.booleans())
def test_valid_streams_cut_anywhere(messages: list[bytes], cuts: list[int], lf_only: bool) -> None:
    data = b"".join(frame(m, b"\n" if lf_only else b"\r\n") for m in messages)
    found = feed_in_pieces(FrameReader(), data, cuts)
    assert found == [Body(m) for m in messages]


noise = st.one_of(
    st.binary(max_size=300),
    st.sampled_from([b"Content-Length: ", b"Content-Length: 12", b"\r\n", b"\n", b"\r", b"content-length:",
                     b"Content-Length: 99999999999999999999\r\n\r\n", b"Content-Length: 7\r\n\r\n",
                     b"Content-Type: x\r\n", b"X: y\r\n" * 40, b"Content-Len", b"{\"jsonrpc\": \"2.0\"",
                     b"Content-Length: 5\r\nContent-Length: 6\r\n"]),
    bodies.map(lambda m: frame(m)[: len(frame(m)) // 2]),
)


@given(st.lists(noise, max_size=8), bodies, bodies, st.lists(st.integers(0, 2000), max_size=6))
def test_the_stream_resynchronises_after_any_bytes(pieces: list[bytes], first: bytes, second: bytes,
                                                    cuts: list[int]) -> None:
    # Garbage that ends in a complete header ("Content-Length:1\n\n") is a frame on the wire: it
    # takes bytes of the frame after it as its body, and no reader can tell. So the promise is that
    # the reader is back in step by the second valid frame, and answers each broken stretch once.
    reader = FrameReader(max_body=10_000)
    garbage = b"".join(pieces)
    cuts = [len(garbage) + c for c in cuts] + [len(garbage)]
    found = feed_in_pieces(reader, garbage + frame(first) + frame(second), cuts)
    assert found and found[-1] == Body(second)
    assert sum(isinstance(f, Problem) and f.reply for f in found) <= len(pieces) + 2


@given(st.lists(noise.filter(lambda b: b"\n" not in b and b"\r" not in b), max_size=8), bodies,
       st.lists(st.integers(0, 2000), max_size=6))
def test_the_next_valid_frame_is_read_after_garbage_without_a_header(pieces: list[bytes], message: bytes,
                                                                   cuts: list[int]) -> None:
    reader = FrameReader(max_body=10_000)
    garbage = b"".join(pieces)
    cuts = [len(garbage) + c for c in cuts] + [len(garbage)]
    found = feed_in_pieces(reader, garbage + frame(message), cuts)
    assert found and found[-1] == Body(message)


def test_a_huge_length_is_refused_without_reading_it() -> None:
    reader = FrameReader()
    found = reader.feed(b"Content-Length: 1000000000000\r\n\r\n" + b"x" * 100_000)
    assert found == [Problem(found[0].message, -32600)]  # type: ignore[union-attr]
    assert reader.pending() < 100  # the bytes after it are searched for a header, not kept
    assert reader.feed(frame(b"{}")) == [Body(b"{}")]


def test_problems_of_one_broken_stretch_are_answered_once() -> None:
    reader = FrameReader()
    found = reader.feed(b"junk\r\n" * 50 + b"Content-Length: x\r\n" + b"more junk\r\n")
    assert [f.reply for f in found if isinstance(f, Problem)][:1] == [True]
    assert sum(f.reply for f in found if isinstance(f, Problem)) == 1
    assert reader.feed(frame(b"{}")) == [Body(b"{}")]
    assert reader.feed(b"junk again\r\n")[0].reply  # type: ignore[union-attr]


def test_a_long_header_line_is_cut_off() -> None:
    reader = FrameReader()
    found = reader.feed(b"X-Long: " + b"a" * (MAX_HEADER_LINE + 10))
    assert isinstance(found[0], Problem)
    assert reader.pending() <= 100


def test_length_too_long_gives_the_body_before_the_next_header() -> None:
    reader = FrameReader()
    found = reader.feed(b"Content-Length: 100\r\n\r\n{\"a\": 1}" + frame(b"[]"))
    assert found == [Body(b"{\"a\": 1}"), Body(b"[]")]


def test_a_header_inside_a_json_string_is_not_a_frame() -> None:
    """A JSON string cannot hold a raw line break, so the text of a header inside one is no header."""
    body = json.dumps({"text": "Content-Length: 12\r\n\r\nabc"}).encode()
    assert FrameReader().feed(frame(body)) == [Body(body)]
