"""Cutting a byte stream into LSP messages (``Content-Length: N`` headers, a blank line, N bytes),
also when the stream is broken.

pygls's reader trusts the stream: a ``Content-Length`` of 10^12 reads until memory runs out, and one
header it does not recognise (LF-only, a wrong name) leaves it waiting for a blank line after a length
it never found, deaf forever. This reader never waits for more than ``max_body`` bytes and, after
anything malformed, resynchronises on the next ``Content-Length`` header.

Why resynchronising is safe: a JSON text cannot contain a raw line break inside a string, so a
complete header line ``Content-Length: 123`` + line break never occurs inside a valid body. A body
that contains one was given a wrong length, and the header that follows is a new frame.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

MAX_BODY = 256 * 1024 * 1024  # a 50 MB document escaped as \uXXXX fits; 10^12 does not
MAX_HEADER_LINE = 8 * 1024
MAX_HEADERS = 32

PARSE_ERROR = -32700
INVALID_REQUEST = -32600

_HEADER_START = re.compile(rb"content-length[ \t]*:", re.IGNORECASE)
_HEADER_IN_BODY = re.compile(rb"content-length[ \t]*:[ \t]*[0-9]+[ \t]*\r?\n", re.IGNORECASE)
_HEADER_LINE = re.compile(rb"([!#$%&'*+.^_`|~0-9A-Za-z-]+)[ \t]*:[ \t]*(.*?)[ \t\r]*")
_LENGTH = re.compile(rb"[0-9]{1,20}")
CR = b"\r"
_KEEP = 64  # bytes kept while searching, in case a header is split between two reads


@dataclass(frozen=True)
class Body:
    """The body of one frame (not yet known to be JSON)."""

    data: bytes


@dataclass(frozen=True)
class Problem:
    """Bytes that are not a frame; ``reply`` is False for later problems of the same broken stretch."""

    message: str
    code: int = PARSE_ERROR
    reply: bool = True


class FrameReader:
    """Incremental: ``feed`` bytes as they arrive, get the bodies and problems found so far."""

    def __init__(self, max_body: int = MAX_BODY) -> None:
        self.max_body = max_body
        self._buffer = bytearray()
        self._state = "headers"  # "headers" | "body" | "resync"
        self._length: int | None = None
        self._headers = 0
        self._scanned = 0  # how far the body (state "body") was searched for a header
        self._skip = 1  # where state "resync" starts searching
        self._troubled = False  # a problem was reported since the last good frame

    def feed(self, data: bytes) -> list[Body | Problem]:
        self._buffer += data
        found: list[Body | Problem] = []
        while self._step(found):
            pass
        return found

    def pending(self) -> int:
        """Bytes held for an incomplete frame (at the end of the stream: a truncated message)."""
        return len(self._buffer.strip()) if self._state == "headers" else len(self._buffer)

    # -- states ---------------------------------------------------------------------------------
    def _step(self, found: list[Body | Problem]) -> bool:
        if self._state == "resync":
            return self._resync()
        if self._state == "body":
            return self._body(found)
        return self._header(found)

    def _header(self, found: list[Body | Problem]) -> bool:
        end = self._buffer.find(b"\n", 0, MAX_HEADER_LINE + 1)
        if end < 0:
            if len(self._buffer) > MAX_HEADER_LINE:
                self._fail(found, f"a header line of more than {MAX_HEADER_LINE} bytes")
                return True
            return False
        line = bytes(self._buffer[:end])
        if not line.strip(b" \t\r"):
            del self._buffer[:end + 1]
            if self._length is not None:
                self._state, self._scanned = "body", 0
            elif self._headers:  # the body follows: search from its first byte
                self._fail(found, "a message without a Content-Length header", skip=0)
            return True  # blank lines between frames are harmless
        match = _HEADER_LINE.fullmatch(line)
        if match is None or _HEADER_START.search(line, 1):  # garbage, or garbage before a header
            self._fail(found, f"not a header: {_preview(line.rstrip(CR))}")
            return True
        name, value = match.group(1).lower(), match.group(2)
        if name == b"content-length":
            self._content_length(found, value)
        else:
            self._headers += 1
            if self._headers > MAX_HEADERS:
                self._fail(found, f"more than {MAX_HEADERS} header lines")
        if self._state == "headers":
            del self._buffer[:end + 1]
        return True

    def _content_length(self, found: list[Body | Problem], value: bytes) -> None:
        if not _LENGTH.fullmatch(value):
            self._fail(found, f"Content-Length is not a number of bytes: {_preview(value)}")
        elif self._length is not None:  # the frame before it lost its blank line: start again here
            self._fail(found, "two Content-Length headers", skip=0)
        elif int(value) > self.max_body:
            self._fail(found, f"a message of {int(value)} bytes is over the limit of {self.max_body} bytes",
                       code=INVALID_REQUEST)
        else:
            self._length = int(value)

    def _body(self, found: list[Body | Problem]) -> bool:
        assert self._length is not None
        end = self._length
        # the first header after the body's start; one that starts inside the claimed body means the
        # length was too long (or the body was cut short) and the next frame began inside this one
        header = _search(_HEADER_IN_BODY, self._buffer, max(0, self._scanned - _KEEP))
        if header is not None and header.start() < self._length:
            end = header.start()
        elif len(self._buffer) < self._length:
            self._scanned = len(self._buffer)
            return False
        with memoryview(self._buffer) as view:
            found.append(Body(view[:end].tobytes()))
        del self._buffer[:end]
        self._reset()
        self._troubled = False
        return True

    def _resync(self) -> bool:
        start = _search(_HEADER_START, self._buffer, self._skip)
        if start is None:
            drop = max(0, len(self._buffer) - _KEEP)
            if drop:  # the failed header is gone with it: search the kept tail from its start
                del self._buffer[:drop]
                self._skip = 0
            return False
        del self._buffer[:start.start()]
        self._reset()
        return True

    # -- helpers --------------------------------------------------------------------------------
    def _fail(self, found: list[Body | Problem], message: str, code: int = PARSE_ERROR,
              skip: int = 1) -> None:
        """Reports the problem (once per broken stretch) and searches for the next header from
        ``skip`` bytes on (1: past the header that failed)."""
        found.append(Problem(message, code, reply=not self._troubled))
        self._troubled = True
        self._reset()
        self._state, self._skip = "resync", skip

    def _reset(self) -> None:
        self._state, self._length, self._headers, self._scanned = "headers", None, 0, 0


def _search(pattern: re.Pattern[bytes], buffer: bytearray, start: int) -> re.Match[bytes] | None:
    """``pattern.search(buffer, start)`` for a pattern that begins with "content-length": a plain
    find of the lower-cased bytes first (a case-insensitive regex search of a 50 MB body takes a
    second; this takes a few milliseconds)."""
    with memoryview(buffer) as view:
        lowered = view[start:].tobytes().lower()
    at = lowered.find(b"content-length")
    while at >= 0:
        match = pattern.match(buffer, start + at)
        if match is not None:
            return match
        at = lowered.find(b"content-length", at + 1)
    return None


def _preview(data: bytes, limit: int = 60) -> str:
    text = data[:limit].decode("utf-8", "replace")
    return repr(text) + ("…" if len(data) > limit else "")
