"""Bad input to rdcd dap: a clear error answer or a clean end, never a traceback or a hang."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from dap_client import ROOT, Client

OBSTACLE = ROOT / "examples" / "obstacle_avoidance.rdcd"


@pytest.fixture
def dap():
    client = Client.start()
    client.request("initialize", {"adapterID": "rdcd"})
    yield client
    assert client.close() == 0
    assert client.problems == []
    stderr = client.process.stderr  # type: ignore[union-attr]
    assert stderr is None or stderr.closed


def launch_error(dap: Client, **arguments: object) -> str:
    response = dap.request("launch", arguments, ok=False)
    assert response["body"]["error"]["showUser"] is True
    return response["message"]


def test_a_missing_program(dap: Client, tmp_path: Path) -> None:
    assert "no-such.rdcd" in launch_error(dap, program=str(tmp_path / "no-such.rdcd"))
    assert "program" in launch_error(dap)


def test_a_broken_program_is_reported_with_its_lines_and_nothing_runs(dap: Client, tmp_path: Path) -> None:
    broken = tmp_path / "broken.rdcd"
    broken.write_text("role A {\n  startup go() { self.nothing(); }\n}\ndeployment { A }\n")
    message = launch_error(dap, program=str(broken), world="lattice")
    assert "error" in message and "nothing runs" in message
    shown = [e["body"] for e in dap.events("output") if e["body"]["category"] == "stderr"]
    assert shown and shown[0]["line"] == 2 and shown[0]["source"]["path"] == str(broken)
    assert f"{broken}:2:" in shown[0]["output"]
    assert dap.events("initialized") == [] and dap.events("stopped") == []
    assert not dap.request("configurationDone", ok=False)["success"]


@pytest.mark.parametrize(("arguments", "words"), [
    ({"duration": -1}, "duration"), ({"duration": "ten"}, "duration"), ({"world": "moon"}, "world"),
    ({"seed": "x"}, "seed"), ({"seed": True}, "seed"), ({"packetLoss": 2}, "packetLoss"),
    ({"obstacle": "tree:3"}, "obstacle"), ({"config": "no-such-car"}, "config"), ({"vm": "z80"}, "vm"),
    ({"stopOnEntry": "yes"}, "stopOnEntry"), ({"duration": 10 ** 400}, "duration"),
])
def test_bad_options(dap: Client, arguments: dict, words: str) -> None:
    message = launch_error(dap, program=str(OBSTACLE), **arguments)
    assert words.lower() in message.lower() or "obstacle" in message.lower()


def test_unknown_threads_frames_references_and_commands(dap: Client) -> None:
    dap.request("launch", {"program": str(OBSTACLE), "world": "lattice", "stopOnEntry": True, "duration": 5})
    dap.request("configurationDone")
    dap.stopped()
    assert "no thread 99" in dap.request("stackTrace", {"threadId": 99}, ok=False)["message"]
    assert "threadId" in dap.request("stackTrace", {"threadId": "1"}, ok=False)["message"]
    assert "no frame" in dap.request("scopes", {"frameId": 12345}, ok=False)["message"]
    assert "no variables" in dap.request("variables", {"variablesReference": 777}, ok=False)["message"]
    assert "not supported" in dap.request("readMemory", {"memoryReference": "0"}, ok=False)["message"]
    assert "address" in dap.request("disassemble", {"memoryReference": "zz", "instructionCount": 3},
                                    ok=False)["message"]
    frame = dap.request("stackTrace", {"threadId": 1})["body"]["stackFrames"][0]
    for bad in ("__import__('os')", "open('x')", "role.__class__", "1 +", "(", "a" * 2000):
        assert not dap.request("evaluate", {"expression": bad, "frameId": frame["id"]}, ok=False)["success"]
    assert not dap.request("launch", {"program": str(OBSTACLE)}, ok=False)["success"]  # launched already
    answer = dap.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": [
        {"line": 2}, {"line": 13, "condition": "role =="}, {"line": 13, "hitCondition": "often"},
        {"line": 9999}, {"line": "x"}]})["body"]["breakpoints"]
    assert answer[0]["verified"] and answer[0]["line"] == 7 and "moved" in answer[0]["message"]
    assert [a["verified"] for a in answer[1:]] == [False, False, True, False]
    other = dap.request("setBreakpoints", {"source": {"path": "/elsewhere/x.rdcd"},
                                           "breakpoints": [{"line": 1}]})
    assert "not the launched program" in other["body"]["breakpoints"][0]["message"]
    assert "unknown filter" in dap.request("setExceptionBreakpoints", {"filters": ["everything"]},
                                           ok=False)["message"]


def test_garbage_frames_are_answered_and_the_session_goes_on(dap: Client) -> None:
    dap.send_raw(b"Content-Length: 5\r\n\r\nhello")
    dap.send_raw(b"this is not a header\r\n\r\n")
    dap.send_raw(b"Content-Length: 2\r\n\r\n[]")
    dap.send_raw(b'Content-Length: 14\r\n\r\n{"type":"xyz"}')
    assert dap.request("threads")["success"]
    said = " ".join(e["body"]["output"] for e in dap.events("output"))
    assert "not JSON" in said and "not a JSON object" in said


def test_a_client_that_vanishes_mid_session_ends_the_adapter() -> None:
    client = Client.start()
    client.request("initialize", {"adapterID": "rdcd"})
    client.request("launch", {"program": str(OBSTACLE), "world": "lattice", "duration": 3000,
                              "obstacle": "none"})
    client.request("configurationDone")
    time.sleep(0.3)
    assert client.process is not None and client.process.stdin is not None
    client.process.stdin.close()  # gone, without a word
    assert client.process.wait(timeout=30) == 0
    assert b"Traceback" not in client.process.stderr.read()  # type: ignore[union-attr]
    client.close()


def test_disconnect_while_stopped_leaves_no_process() -> None:
    client = Client.start()
    client.launch(OBSTACLE, stopOnEntry=True, world="lattice", duration=5)
    client.stopped()
    client.request("disconnect", {"terminateDebuggee": True})
    assert client.process is not None and client.process.wait(timeout=20) == 0
    client.close()
    assert client.problems == []


def _listening(process: subprocess.Popen[bytes]) -> tuple[str, int, str]:
    assert process.stderr is not None
    seen = b""
    while b"listening on" not in seen:
        line = process.stderr.readline()
        assert line, seen.decode()
        seen += line
    match = re.search(rb"listening on (\S+):(\d+)", seen)
    assert match
    return match.group(1).decode(), int(match.group(2)), seen.decode()


def test_a_port_listens_on_this_machine_only_by_default() -> None:
    process = subprocess.Popen([sys.executable, "-m", "rdcd_core", "dap", "--port", "0"], cwd=ROOT,
                               stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        host, port, said = _listening(process)
        assert host == "127.0.0.1" and "warning" not in said
        with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
            client = Client(sock=sock)
            assert client.request("initialize", {"adapterID": "rdcd"})["body"]["supportsStepBack"] is True
            client.request("disconnect")
            assert client.problems == []
    finally:
        process.kill()
        process.wait()
        process.stderr.close()  # type: ignore[union-attr]


def test_another_host_is_warned_about() -> None:
    process = subprocess.Popen([sys.executable, "-m", "rdcd_core", "dap", "--port", "0", "--host", "0.0.0.0"],
                               cwd=ROOT, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE)
    try:
        host, _, said = _listening(process)
        assert host == "0.0.0.0" and "warning" in said
    finally:
        process.kill()
        process.wait()
        process.stderr.close()  # type: ignore[union-attr]
