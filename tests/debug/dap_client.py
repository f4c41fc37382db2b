"""A DAP client for the tests: starts ``rdcd dap`` (or talks to a socket), sends requests, and
checks EVERY message the adapter sends against the official DAP JSON schema (pinned in
``schema/``): the base protocol message, then the definition of that response or event."""

from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
import time
from functools import cache
from pathlib import Path
from typing import Any

import jsonschema

SCHEMA = Path(__file__).parent / "schema" / "debugAdapterProtocol.json"
ROOT = Path(__file__).resolve().parents[2]
TIMEOUT = 60.0


@cache
def _definitions() -> dict[str, Any]:
    return json.loads(SCHEMA.read_text(encoding="utf-8"))["definitions"]


@cache
def _validator(name: str) -> jsonschema.Draft4Validator:
    return jsonschema.Draft4Validator({"$ref": f"#/definitions/{name}", "definitions": _definitions()})


# The adapter's own events (DAP lets an adapter add events; a client ignores those it does not know).
CUSTOM_EVENTS: dict[str, dict[str, Any]] = {
    "rdcd/moment": {
        "type": "object", "required": ["body"],
        "properties": {"body": {
            "type": "object", "required": ["t", "module", "run"], "additionalProperties": False,
            "properties": {"t": {"type": "number", "minimum": 0},
                           "module": {"type": ["integer", "null"], "minimum": 0},
                           "run": {"type": "object", "required": ["world", "config", "duration_s", "seed",
                                                                  "source_sha256"]}}}}},
}


def schema_problems(message: dict[str, Any]) -> list[str]:
    """What is wrong with a message from the adapter (empty: it follows the schema)."""
    names = ["ProtocolMessage"]
    if message.get("type") == "response":
        names.append("Response")
        if message.get("success") is False:
            names.append("ErrorResponse")
        else:
            command = str(message.get("command", ""))
            specific = command[:1].upper() + command[1:] + "Response"
            if specific in _definitions():
                names.append(specific)
    elif message.get("type") == "event":
        names.append("Event")
        event = str(message.get("event", ""))
        specific = event[:1].upper() + event[1:] + "Event"
        if specific in _definitions():
            names.append(specific)
        elif event in CUSTOM_EVENTS:
            out = [f"{event}: {'/'.join(map(str, e.absolute_path))}: {e.message}"
                   for e in jsonschema.Draft4Validator(CUSTOM_EVENTS[event]).iter_errors(message)]
            if out:
                return out
        else:
            return [f"no event {event!r} in the protocol"]
    else:
        return [f"an adapter sends responses and events, not {message.get('type')!r}"]
    out = []
    for name in names:
        for error in _validator(name).iter_errors(message):
            out.append(f"{name}: {'/'.join(map(str, error.absolute_path))}: {error.message}")
    return out


class DapError(AssertionError):
    pass


class Client:
    def __init__(self, process: subprocess.Popen[bytes] | None = None, sock: Any = None,
                 validate: bool = True) -> None:
        self.process = process
        self.validate = validate  # benchmarks time the adapter, not the schema check
        self.sock = sock
        self.messages: list[dict[str, Any]] = []
        self.problems: list[str] = []
        self._queue: queue.Queue[dict[str, Any] | None] = queue.Queue()
        self._pending: list[dict[str, Any]] = []
        self._seq = 0
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    @classmethod
    def start(cls, *extra: str, validate: bool = True) -> Client:
        env = dict(os.environ, PYTHONUNBUFFERED="1")
        process = subprocess.Popen([sys.executable, "-m", "rdcd_core", "dap", *extra], stdin=subprocess.PIPE,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT, env=env)
        return cls(process, validate=validate)

    # ---- reading ---------------------------------------------------------------------------
    def _raw_read(self, n: int) -> bytes:
        if self.sock is not None:
            return self.sock.recv(n)
        assert self.process is not None and self.process.stdout is not None
        return self.process.stdout.read1(n)  # type: ignore[attr-defined]

    def _read(self) -> None:
        buffer = b""
        try:
            while True:
                while b"\r\n\r\n" not in buffer:
                    data = self._raw_read(65536)
                    if not data:
                        return
                    buffer += data
                head, _, buffer = buffer.partition(b"\r\n\r\n")
                length = int(head.split(b":")[1])
                while len(buffer) < length:
                    data = self._raw_read(65536)
                    if not data:
                        self.problems.append("the stream ended inside a message")
                        return
                    buffer += data
                body, buffer = buffer[:length], buffer[length:]
                message = json.loads(body)
                self.messages.append(message)
                label = self._label(message)
                if self.validate:
                    self.problems += [f"{label}: {p}" for p in schema_problems(message)]
                self._queue.put(message)
        except (OSError, ValueError) as e:
            self.problems.append(f"unreadable output: {e}")
        finally:
            self._queue.put(None)

    def _next(self, timeout: float) -> dict[str, Any]:
        try:
            message = self._queue.get(timeout=timeout)
        except queue.Empty:
            seen = [self._label(m) for m in self.messages[-10:]]
            raise DapError(f"no message in {timeout} s; seen: {seen}") from None
        if message is None:
            self._queue.put(None)
            raise DapError("the adapter closed its output")
        return message

    @staticmethod
    def _label(m: dict[str, Any]) -> str:
        return f"{m.get('type')}:{m.get('command') or m.get('event')}"

    # ---- writing ---------------------------------------------------------------------------
    def send_raw(self, data: bytes) -> None:
        if self.sock is not None:
            self.sock.sendall(data)
        else:
            assert self.process is not None and self.process.stdin is not None
            self.process.stdin.write(data)
            self.process.stdin.flush()

    def send(self, command: str, arguments: dict[str, Any] | None = None) -> int:
        self._seq += 1
        message: dict[str, Any] = {"seq": self._seq, "type": "request", "command": command}
        if arguments is not None:
            message["arguments"] = arguments
        body = json.dumps(message).encode()
        self.send_raw(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        return self._seq

    def request(self, command: str, arguments: dict[str, Any] | None = None, *, ok: bool = True,
                timeout: float = TIMEOUT) -> dict[str, Any]:
        seq = self.send(command, arguments)
        response = self.wait(lambda m: m.get("type") == "response" and m.get("request_seq") == seq, timeout)
        if ok and not response["success"]:
            raise DapError(f"{command} failed: {response.get('message')}")
        if not ok and response["success"]:
            raise DapError(f"{command} succeeded, expected an error")
        return response

    def wait(self, predicate: Any, timeout: float = TIMEOUT) -> dict[str, Any]:
        for i, m in enumerate(self._pending):
            if predicate(m):
                return self._pending.pop(i)
        end = time.monotonic() + timeout
        while True:
            m = self._next(max(0.01, end - time.monotonic()))
            if predicate(m):
                return m
            self._pending.append(m)

    def event(self, name: str, timeout: float = TIMEOUT) -> dict[str, Any]:
        return self.wait(lambda m: m.get("type") == "event" and m.get("event") == name, timeout)

    def events(self, name: str) -> list[dict[str, Any]]:
        return [m for m in self.messages if m.get("type") == "event" and m.get("event") == name]

    # ---- sessions --------------------------------------------------------------------------
    def launch(self, program: str | Path, *, breakpoints: list[dict[str, Any]] | None = None,
               function_breakpoints: list[str] | None = None, filters: list[str] | None = None,
               **arguments: Any) -> dict[str, Any]:
        """initialize, launch, breakpoints, configurationDone; the launch response."""
        self.request("initialize", {"adapterID": "rdcd", "linesStartAt1": True, "columnsStartAt1": True,
                                    "pathFormat": "path", "supportsVariableType": True})
        launched = self.request("launch", {"program": str(program), **arguments})
        self.event("initialized")
        if breakpoints is not None:
            self.bp_response = self.request("setBreakpoints", {"source": {"path": str(program)},
                                                               "breakpoints": breakpoints})
        if function_breakpoints is not None:
            self.request("setFunctionBreakpoints",
                         {"breakpoints": [{"name": n} for n in function_breakpoints]})
        self.request("setExceptionBreakpoints", {"filters": filters or []})
        self.request("configurationDone")
        return launched

    def stopped(self, timeout: float = TIMEOUT) -> dict[str, Any]:
        return self.wait(lambda m: m.get("type") == "event" and m.get("event") in ("stopped", "terminated"),
                         timeout)

    def close(self) -> int | None:
        """Disconnect (if still connected) and wait for the adapter to end: its exit status."""
        if self.process is None:
            return None
        if self.process.poll() is None:
            try:
                self.request("disconnect", {"terminateDebuggee": True}, timeout=20)
            except (DapError, OSError):
                pass
        try:
            return self.process.wait(timeout=20)
        finally:
            if self.process.poll() is None:
                self.process.kill()
                self.process.wait()
            for stream in (self.process.stdin, self.process.stdout, self.process.stderr):
                if stream is not None:
                    stream.close()
