"""One DAP channel: ``Content-Length`` frames in (``server.framing.FrameReader``, which survives
broken input), JSON messages out with their sequence numbers, from any thread."""

from __future__ import annotations

import json
import threading
from collections.abc import Callable, Iterator
from typing import Any

from server.framing import Body, FrameReader, Problem

READ_SIZE = 65536


class ChannelClosed(Exception):
    pass


class Channel:
    def __init__(self, read: Callable[[int], bytes], write: Callable[[bytes], Any]) -> None:
        self._read, self._write = read, write
        self._reader = FrameReader()
        self._lock = threading.Lock()
        self._seq = 0
        self.closed = False
        self.sent: list[dict[str, Any]] | None = None  # tests may keep what was sent

    def messages(self) -> Iterator[dict[str, Any] | str]:
        """Each message read (a dict), or a string saying what was wrong with a frame; ends when
        the other side closes the stream."""
        while not self.closed:
            try:
                data = self._read(READ_SIZE)
            except (OSError, ValueError):
                data = b""
            if not data:
                return
            for item in self._reader.feed(data):
                if isinstance(item, Problem):
                    if item.reply:
                        yield item.message
                    continue
                assert isinstance(item, Body)
                try:
                    message = json.loads(item.data.decode("utf-8"))
                except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as e:
                    yield f"a message that is not JSON ({e})"
                    continue
                if not isinstance(message, dict):
                    yield "a message that is not a JSON object"
                    continue
                yield message

    def send(self, message: dict[str, Any]) -> None:
        with self._lock:
            if self.closed:
                return
            self._seq += 1
            message = {"seq": self._seq, **message}
            body = json.dumps(message, ensure_ascii=False, allow_nan=False).encode("utf-8")
            try:
                self._write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
            except (OSError, ValueError):
                self.closed = True  # the client went away: nothing more to say
                return
            if self.sent is not None:
                self.sent.append(message)

    def event(self, name: str, body: dict[str, Any] | None = None) -> None:
        message: dict[str, Any] = {"type": "event", "event": name}
        if body is not None:
            message["body"] = body
        self.send(message)

    def respond(self, request: dict[str, Any], body: dict[str, Any] | None = None) -> None:
        message: dict[str, Any] = {"type": "response", "request_seq": request.get("seq", 0), "success": True,
                                   "command": str(request.get("command", ""))}
        if body is not None:
            message["body"] = body
        self.send(message)

    def fail(self, request: dict[str, Any], text: str, ident: int = 1) -> None:
        seq = request.get("seq", 0)
        self.send({"type": "response", "request_seq": seq if isinstance(seq, int) else 0, "success": False,
                   "command": str(request.get("command", "")), "message": text,
                   "body": {"error": {"id": ident, "format": text.replace("{", "(").replace("}", ")"),
                                      "showUser": True}}})
