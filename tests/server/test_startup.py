"""``rdcd-lsp`` start-up with unusable options: one line on stderr and status 2 for the command line,
one line and the default for the environment, a logged warning and the old value for the client's
settings; never a traceback, never a server that does not publish."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.server.rawclient import ROOT, RawServer, frame, notification

URI = "file:///virtual/startup.rdcd"
TEXT = "role A { }\ndeployment { A }\n"


def run(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    environment = dict(os.environ, PYTHONPATH=str(ROOT), **(env or {}))
    return subprocess.run([sys.executable, "-m", "server", *args], cwd=str(ROOT), env=environment,
                          input=b"", capture_output=True, timeout=60)


def one_line(stderr: bytes) -> str:
    text = stderr.decode()
    assert "Traceback" not in text, text
    lines = text.strip().splitlines()
    assert len(lines) == 1, text
    return lines[0]


def test_log_file_in_a_missing_folder(tmp_path: Path) -> None:
    done = run("--log-file", str(tmp_path / "no" / "such" / "server.log"))
    assert done.returncode == 2
    assert "cannot write the log file" in one_line(done.stderr)


def test_log_file_naming_a_folder(tmp_path: Path) -> None:
    done = run("--log-file", str(tmp_path))
    assert done.returncode == 2
    assert "folder" in one_line(done.stderr)


def test_log_file_that_cannot_be_written(tmp_path: Path) -> None:
    target = tmp_path / "locked.log"
    target.write_text("")
    target.chmod(0o400)
    if os.access(target, os.W_OK):
        pytest.skip("running as a user who can write anything")
    done = run("--log-file", str(target))
    assert done.returncode == 2
    assert "locked.log" in one_line(done.stderr)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_log_that_fails_on_every_write_prints_no_traceback() -> None:
    server = RawServer("--log-file", "/dev/full", log_level="DEBUG")
    try:
        server.initialize()
        assert server.stop() == 0
        assert server.stderr_text() == ""
    finally:
        server.kill()


def test_log_file_is_appended(tmp_path: Path) -> None:
    log = tmp_path / "server.log"
    log.write_text("earlier lines\n")
    server = RawServer("--log-file", str(log), log_level="INFO")
    try:
        server.initialize()
        assert server.stop() == 0
    finally:
        server.kill()
    assert log.read_text().startswith("earlier lines\n")


BAD_DEBOUNCE = ["abc", "", "inf", "-inf", "nan", "NaN", "-1", "1e300", "10001", "1e999", "0x10", "5 ms"]


@pytest.mark.parametrize("value", BAD_DEBOUNCE)
def test_bad_debounce_on_the_command_line(value: str) -> None:
    done = run(f"--debounce-ms={value}")
    assert done.returncode == 2
    assert "--debounce-ms" in one_line(done.stderr)


@pytest.mark.parametrize("value", ["abc", "inf", "nan", "-5", "1e400", "99999999"])
def test_bad_debounce_in_the_environment_falls_back_and_publishes(value: str) -> None:
    text = _serve_with_debounce_variable(value)
    assert "Traceback" not in text
    assert "RDCD_LSP_DEBOUNCE_MS" in text.splitlines()[0]


def test_good_debounce_in_the_environment() -> None:
    assert "RDCD_LSP_DEBOUNCE_MS" not in _serve_with_debounce_variable(" 5 ")


def _serve_with_debounce_variable(value: str) -> str:
    """The server's stderr after it started with RDCD_LSP_DEBOUNCE_MS=value, published the
    diagnostics of an opened document and shut down cleanly."""
    server = RawServer(env=dict(os.environ, RDCD_LSP_DEBOUNCE_MS=value))
    try:
        server.initialize()
        opened(server)
        assert server.stop() == 0
    finally:
        server.kill()
    return server.stderr_text()


BAD_SETTINGS = [
    {"rdcd": {"diagnostics": {"debounceMs": math.inf}}},  # sent as 1e999: valid JSON, read as infinity
    {"rdcd": {"diagnostics": {"debounceMs": -1}}},
    {"rdcd": {"diagnostics": {"debounceMs": 10**30}}},
    {"rdcd": {"diagnostics": {"debounceMs": "soon"}}},
    {"rdcd": {"diagnostics": {"debounceMs": [5]}}},
    {"rdcd": {"diagnostics": {"debounceMs": True}}},
    {"rdcd.diagnostics.debounceMs": "inf"},
    {"rdcd": {"inlayHints": {"fragmentSizes": "yes"}}},
    {"rdcd": "nonsense"},
    [1, 2, 3],
]


def dumps(message: object) -> bytes:
    """JSON with infinity written as 1e999 (Python would write Infinity, which is not JSON)."""
    return json.dumps(message).replace("Infinity", "1e999").encode()


@pytest.mark.parametrize("options", BAD_SETTINGS[:6] + BAD_SETTINGS[-1:])
def test_bad_initialization_options_still_publish(options: object) -> None:
    server = RawServer("--debounce-ms", "5")
    try:
        server.send(frame(dumps({"jsonrpc": "2.0", "id": "init", "method": "initialize", "params": {
            "processId": None, "rootUri": None, "capabilities": {}, "initializationOptions": options}})))
        assert "result" in server.answer("init")
        server.send(notification("initialized", {}))
        opened(server)
        assert server.stop() == 0
    finally:
        server.kill()
    assert "Traceback" not in server.stderr_text()
    if isinstance(options, dict):
        assert "setting ignored" in server.stderr_text()


def test_bad_configuration_changes_still_publish() -> None:
    server = RawServer("--debounce-ms", "5")
    try:
        server.initialize()
        for number, options in enumerate(BAD_SETTINGS):
            server.send(frame(dumps({"jsonrpc": "2.0", "method": "workspace/didChangeConfiguration",
                                     "params": {"settings": options}})))
            opened(server, f"file:///virtual/configured-{number}.rdcd")
        assert server.stop() == 0
    finally:
        server.kill()
    assert "Traceback" not in server.stderr_text()
    assert server.stderr_text().count("setting ignored") >= len(BAD_SETTINGS) - 2


def opened(server: RawServer, uri: str = URI) -> None:
    """didOpen is answered with diagnostics (a server with an infinite debounce would never send them)."""
    server.send(notification("textDocument/didOpen", {"textDocument": {
        "uri": uri, "languageId": "rdcd", "version": 1, "text": TEXT}}))
    assert server.published(uri, timeout=30)["params"]["diagnostics"] == []
