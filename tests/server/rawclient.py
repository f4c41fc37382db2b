"""A raw LSP client over stdio: writes any bytes to the server, reads its frames strictly.

pytest-lsp cannot send a malformed frame; this one can. Everything the server writes is checked on
the way in: a well-formed frame (exact Content-Length, UTF-8 JSON), a JSON-RPC 2.0 message, and no
Python traceback in an error's ``data``.
"""

from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]


def frame(message: Any, *, newline: bytes = b"\r\n") -> bytes:
    body = message if isinstance(message, bytes) else json.dumps(message).encode()
    return b"Content-Length: %d" % len(body) + newline + newline + body


def request(msg_id: Any, method: str, params: Any = None) -> bytes:
    message: dict[str, Any] = {"jsonrpc": "2.0", "id": msg_id, "method": method}
    if params is not None:
        message["params"] = params
    return frame(message)


def notification(method: str, params: Any = None) -> bytes:
    message: dict[str, Any] = {"jsonrpc": "2.0", "method": method}
    if params is not None:
        message["params"] = params
    return frame(message)


class RawServer:
    def __init__(self, *args: str, env: dict[str, str] | None = None, log_level: str = "INFO") -> None:
        environment = dict(os.environ if env is None else env)
        environment["PYTHONPATH"] = str(ROOT)
        self.process = subprocess.Popen(
            [sys.executable, "-m", "server", "--log-level", log_level, *args], cwd=str(ROOT),
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=environment)
        self.messages: queue.Queue[dict | None] = queue.Queue()
        self.received: list[dict] = []
        self.stderr = bytearray()
        self.problems: list[str] = []  # malformed output of the server
        threading.Thread(target=self._read_stdout, daemon=True).start()
        threading.Thread(target=self._read_stderr, daemon=True).start()

    # -- writing ----------------------------------------------------------------------------------
    def send(self, data: bytes) -> None:
        assert self.process.stdin is not None
        self.process.stdin.write(data)
        self.process.stdin.flush()

    def initialize(self, options: Any = None, msg_id: Any = "init") -> dict:
        params: dict[str, Any] = {"processId": None, "rootUri": None, "capabilities": {}}
        if options is not None:
            params["initializationOptions"] = options
        self.send(request(msg_id, "initialize", params))
        answer = self.answer(msg_id)
        self.send(notification("initialized", {}))
        return answer

    def stop(self, timeout: float = 20) -> int:
        """shutdown, exit; the exit status."""
        self.send(request("bye", "shutdown"))
        assert "error" not in self.answer("bye")
        self.send(notification("exit"))
        return self.wait(timeout)

    def wait(self, timeout: float = 20) -> int:
        try:
            return self.process.wait(timeout=timeout)
        finally:
            self.kill()

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()

    # -- reading ----------------------------------------------------------------------------------
    def answer(self, msg_id: Any, timeout: float = 30) -> dict:
        """The answer to request ``msg_id`` (also one received earlier)."""
        return self.next_message(lambda m: m.get("id") == msg_id and "method" not in m, timeout)

    def next_message(self, wanted: Any, timeout: float = 30) -> dict:
        for message in self.received:
            if wanted(message):
                self.received.remove(message)
                return message
        deadline = time.monotonic() + timeout
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError(f"no such message; stderr: {self.stderr_text()[-2000:]}")
            try:
                message = self.messages.get(timeout=remaining)
            except queue.Empty:
                continue
            if message is None:
                self.messages.put(None)
                raise AssertionError(f"the server closed its output; stderr: {self.stderr_text()[-2000:]}")
            if wanted(message):
                return message
            self.received.append(message)

    def published(self, uri: str, timeout: float = 30) -> dict:
        return self.next_message(lambda m: m.get("method") == "textDocument/publishDiagnostics"
                                 and m["params"]["uri"] == uri, timeout)

    def stderr_text(self) -> str:
        return self.stderr.decode("utf-8", "replace")

    def _read_stdout(self) -> None:
        stream = self.process.stdout
        assert stream is not None
        try:
            while True:
                length = None
                while True:
                    line = stream.readline()
                    if not line:
                        return
                    if line == b"\r\n":
                        break
                    if not line.endswith(b"\r\n"):
                        self.problems.append(f"header line without CRLF: {line!r}")
                    name, _, value = line.decode("ascii").partition(":")
                    if name.lower() == "content-length":
                        length = int(value)
                if length is None:
                    self.problems.append("a frame without Content-Length")
                    return
                body = stream.read(length)
                message = json.loads(body.decode("utf-8"))
                self._check(message)
                self.messages.put(message)
        except Exception as error:  # noqa: BLE001 - recorded, the test fails on it
            self.problems.append(f"unreadable output: {error!r}")
        finally:
            self.messages.put(None)

    def _check(self, message: Any) -> None:
        if not isinstance(message, dict) or message.get("jsonrpc") != "2.0":
            self.problems.append(f"not a JSON-RPC message: {message!r}")
            return
        error = message.get("error")
        if error is not None:
            if "traceback" in json.dumps(error).lower():
                self.problems.append(f"a traceback in an error answer: {error!r}")
            if "\n" in error.get("message", ""):
                self.problems.append(f"an error message of several lines: {error!r}")

    def _read_stderr(self) -> None:
        stream = self.process.stderr
        assert stream is not None
        while chunk := stream.read1(65536):
            self.stderr += chunk
