"""rdcd dap end to end: a real adapter process driven by a DAP client that checks every message
it sends against the protocol's schema."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import pytest
from dap_client import ROOT, Client

OBSTACLE = ROOT / "examples" / "obstacle_avoidance.rdcd"
SNAKE = ROOT / "examples" / "snake_wave.rdcd"
STORE_FULL = ROOT / "tests" / "debug" / "data" / "store_full.rdcd"
HANDLER_LINE = 13  # { self.disableEvent(event_handler); Wheel.stop(); }
LATTICE = {"world": "lattice", "obstacle": "wall:0.1", "duration": 8}


@pytest.fixture
def dap():
    client = Client.start()
    yield client
    status = client.close()
    assert status == 0
    assert client.problems == []


def top_frame(dap: Client, thread: int) -> dict[str, Any]:
    return dap.request("stackTrace", {"threadId": thread})["body"]["stackFrames"][0]


def scope(dap: Client, frame_id: int, name: str) -> dict[str, str]:
    scopes = dap.request("scopes", {"frameId": frame_id})["body"]["scopes"]
    ref = next(s["variablesReference"] for s in scopes if s["name"] == name)
    variables = dap.request("variables", {"variablesReference": ref})["body"]["variables"]
    return {v["name"]: v["value"] for v in variables}


def tree(dap: Client, ref: int) -> Any:
    if ref == 0:
        return None
    return {v["name"]: (v["value"], tree(dap, v["variablesReference"]))
            for v in dap.request("variables", {"variablesReference": ref})["body"]["variables"]}


def world_state(dap: Client) -> dict[str, Any]:
    """Every variable of every module, as the client sees it."""
    state = {}
    for thread in dap.request("threads")["body"]["threads"]:
        frames = dap.request("stackTrace", {"threadId": thread["id"]})["body"]["stackFrames"]
        shown = []
        for frame in frames:
            scopes = dap.request("scopes", {"frameId": frame["id"]})["body"]["scopes"]
            shown.append((frame["name"], frame["line"], frame.get("instructionPointerReference"),
                          {s["name"]: tree(dap, s["variablesReference"]) for s in scopes}))
        state[thread["name"]] = shown
    return state


def run_to_handler(dap: Client, **extra: Any) -> dict[str, Any]:
    """Continue until the breakpoint on the handler line stops inside the handler itself."""
    for _ in range(20):
        stop = dap.stopped()
        assert stop["event"] == "stopped", "the run ended before the handler ran"
        thread = stop["body"]["threadId"]
        if "handler" in top_frame(dap, thread)["name"]:
            return stop
        dap.request("continue", {"threadId": thread})
    raise AssertionError("no stop in the handler")


def test_a_breakpoint_on_the_handler_line_stops_the_world_on_a_wheel(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE}], **LATTICE)
    answer = dap.bp_response["body"]["breakpoints"][0]
    assert answer["verified"] and answer["line"] == HANDLER_LINE
    stop = run_to_handler(dap)
    body = stop["body"]
    assert body["reason"] == "breakpoint" and body["allThreadsStopped"] is True
    assert body["hitBreakpointIds"] == [answer["id"]]
    assert "t = 3.0" in body["description"]
    frame = top_frame(dap, body["threadId"])
    assert frame["line"] == HANDLER_LINE and frame["source"]["path"] == str(OBSTACLE)
    module = scope(dap, frame["id"], "Module")
    assert module["role"] in ("LeftWheel", "RightWheel")
    assert module["module"] == str(body["threadId"] - 1)
    threads = dap.request("threads")["body"]["threads"]
    assert len(threads) == 7 and any("Axle" in t["name"] for t in threads)
    assert dap.request("evaluate", {"expression": "role", "frameId": frame["id"], "context": "watch"}
                       )["body"]["result"] == module["role"]
    assert dap.request("evaluate", {"expression": "sensor1 or sensor5", "frameId": frame["id"]}
                       )["body"]["result"] == "true"
    stack = scope(dap, frame["id"], "Operand stack")
    assert "pc" in stack
    handlers = dap.request("scopes", {"frameId": frame["id"]})["body"]["scopes"]
    assert [s["name"] for s in handlers][:2] == ["Module", "Operand stack"]
    dap.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": []})
    dap.request("continue", {"threadId": body["threadId"]})
    assert dap.stopped()["event"] == "terminated"


def test_conditions_pick_the_module(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE, "condition": "module == 4"}], **LATTICE)
    seen = set()
    while (stop := dap.stopped())["event"] == "stopped":
        seen.add(stop["body"]["threadId"])
        dap.request("continue", {"threadId": stop["body"]["threadId"]})
    assert seen == {5}


def test_a_role_condition_and_a_hit_count(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE, "condition": 'role == "LeftWheel"',
                                       "hitCondition": "2"}], **LATTICE)
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["threadId"] == 4
    frame = top_frame(dap, 4)
    assert "handler" in frame["name"]  # the first hit (installing the handler) was counted, not shown


def test_log_points_print_and_do_not_stop(dap: Client) -> None:
    message = "module {module} is {role} at {time}"
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE, "logMessage": message}], **LATTICE)
    assert dap.stopped()["event"] == "terminated"
    logged = [e["body"] for e in dap.events("output") if "is LeftWheel" in e["body"]["output"]
              or "is RightWheel" in e["body"]["output"]]
    assert logged and all(b["line"] == HANDLER_LINE for b in logged)
    assert any(b["output"].startswith("module 3 is LeftWheel at 3.0") for b in logged)
    assert dap.events("stopped") == []


def test_a_function_breakpoint_on_a_command(dap: Client) -> None:
    dap.launch(OBSTACLE, function_breakpoints=["Wheel.stop", "Wheel.nothing"], **LATTICE)
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["reason"] == "function breakpoint"
    frame = top_frame(dap, stop["body"]["threadId"])
    assert 16 <= frame["line"] <= 22 and "command" in frame["name"]


def test_an_exception_breakpoint_on_a_runtime_error(dap: Client) -> None:
    # a module runs out of program slots while installing handlers: a runtime error of the VM
    dap.launch(STORE_FULL, filters=["runtime"], world="lattice", config="snake5", obstacle="none", duration=5)
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["reason"] == "exception"
    assert "program slots are in use" in stop["body"]["text"]
    info = dap.request("exceptionInfo", {"threadId": stop["body"]["threadId"]})["body"]
    assert "program slots are in use" in info["description"]
    frame = top_frame(dap, stop["body"]["threadId"])
    assert frame["line"] > 0


def test_stepping_by_statement_and_by_instruction_with_the_disassembly(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE}], **LATTICE)
    stop = run_to_handler(dap)
    thread = stop["body"]["threadId"]
    dap.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": []})
    before = top_frame(dap, thread)
    dap.request("stepIn", {"threadId": thread, "granularity": "instruction"})
    stop = dap.stopped()
    assert stop["body"]["reason"] == "step" and stop["body"]["threadId"] == thread
    after = top_frame(dap, thread)
    assert int(after["instructionPointerReference"], 16) > int(before["instructionPointerReference"], 16)
    listing = dap.request("disassemble", {"memoryReference": after["instructionPointerReference"],
                                          "instructionOffset": -2, "instructionCount": 6,
                                          "resolveSymbols": True})["body"]["instructions"]
    assert len(listing) == 6 and listing[2]["address"] == after["instructionPointerReference"]
    assert any(i.get("line") == HANDLER_LINE for i in listing)
    dap.request("next", {"threadId": thread})
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["reason"] == "step"
    assert stop["body"]["threadId"] == thread


def test_stepping_back_and_forward_again_gives_the_same_states(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE}], **LATTICE)
    stop = run_to_handler(dap)
    thread = stop["body"]["threadId"]
    dap.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": []})
    forward = [(stop["body"]["description"], world_state(dap))]
    for _ in range(3):
        dap.request("next", {"threadId": thread, "granularity": "instruction"})
        forward.append((dap.stopped()["body"]["description"], world_state(dap)))
    assert len({str(state) for _, state in forward}) == 4  # every step changed something
    for i in (2, 1, 0):
        dap.request("stepBack", {"threadId": thread, "granularity": "instruction"})
        stop = dap.stopped()
        assert stop["body"]["reason"] == "step"
        assert world_state(dap) == forward[i][1]
        assert stop["body"]["description"].split(" at ")[1] == forward[i][0].split(" at ")[1]
    for i in (1, 2, 3):
        dap.request("next", {"threadId": thread, "granularity": "instruction"})
        assert (dap.stopped()["body"]["description"], world_state(dap)) == forward[i]
    # by statements: forward, back, forward again
    dap.request("next", {"threadId": thread})
    dap.stopped()
    ahead = world_state(dap)
    dap.request("stepBack", {"threadId": thread})
    dap.stopped()
    assert world_state(dap) != ahead
    dap.request("next", {"threadId": thread})
    dap.stopped()
    assert world_state(dap) == ahead


def moments_match_stops(dap: Client) -> list[tuple[float, int | None]]:
    """Each stopped event is followed by one rdcd/moment with its time and module: the moments."""
    stops, moments = dap.events("stopped"), dap.events("rdcd/moment")
    assert len(moments) == len(stops) > 0
    out = []
    for stop, moment in zip(stops, moments, strict=True):
        t, module = moment["body"]["t"], moment["body"]["module"]
        assert dap.messages.index(moment) > dap.messages.index(stop)
        assert stop["body"]["description"].endswith(f" at t = {t:.3f} s")
        assert module is None or module == stop["body"]["threadId"] - 1
        out.append((t, module))
    return out


def test_every_stop_sends_the_moment_for_the_replay_panel(dap: Client) -> None:
    dap.launch(OBSTACLE, stopOnEntry=True, breakpoints=[{"line": HANDLER_LINE}], **LATTICE)
    assert dap.stopped()["body"]["reason"] == "entry"
    dap.request("continue", {"threadId": 1})
    stop = run_to_handler(dap)
    thread = stop["body"]["threadId"]
    dap.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": []})
    for _ in range(2):
        dap.request("next", {"threadId": thread, "granularity": "instruction"})
        dap.stopped()
    dap.request("stepBack", {"threadId": thread, "granularity": "instruction"})
    dap.stopped()
    dap.request("continue", {"threadId": thread})
    assert dap.stopped()["event"] == "terminated"
    moments = moments_match_stops(dap)
    assert moments[0] == (0.0, None)  # the start: no module runs yet
    handler = moments[len(moments) - 4]
    assert 3.0 <= handler[0] < 3.1 and handler[1] == thread - 1  # the wheel that hit the breakpoint
    assert all(m[1] == thread - 1 for m in moments[-3:])
    assert moments[-3][0] >= handler[0]
    assert moments[-1] == moments[-3]  # two steps and one back: the moment after the first step


def test_reverse_continue_returns_to_the_last_breakpoint(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE}], **LATTICE)
    first = dap.stopped()
    state = world_state(dap)
    dap.request("continue", {"threadId": first["body"]["threadId"]})
    second = dap.stopped()
    assert second["body"]["description"] != first["body"]["description"]
    dap.request("reverseContinue", {"threadId": second["body"]["threadId"]})
    back = dap.stopped()
    assert back["body"]["description"] == first["body"]["description"]
    assert back["body"]["hitBreakpointIds"] == first["body"]["hitBreakpointIds"]
    assert world_state(dap) == state


def test_stop_on_entry_pause_and_terminate(dap: Client) -> None:
    dap.launch(OBSTACLE, stopOnEntry=True, world="lattice", duration=3000, obstacle="none")
    stop = dap.stopped()
    assert stop["body"]["reason"] == "entry" and "t = 0.000 s" in stop["body"]["description"]
    frame = top_frame(dap, stop["body"]["threadId"])
    assert frame["line"] == 0  # nothing runs yet
    dap.request("continue", {"threadId": 1})
    dap.request("pause", {"threadId": 1})
    assert dap.stopped()["body"]["reason"] == "pause"
    dap.request("terminate")
    dap.event("terminated")


@pytest.mark.parametrize(("world", "obstacle", "duration", "look"), [
    ("lattice", "wall:0.1", "8", False), ("physics", "wall:0.3", "6", True)])
def test_a_debugged_run_is_the_simulate_run(dap: Client, world: str, obstacle: str, duration: str,
                                            look: bool, tmp_path: Path) -> None:
    """Without breakpoints, or stopping and reading every variable of every module on the way
    (reading changes nothing), the run ends as ``rdcd simulate`` ends."""
    import subprocess
    import sys

    if look:
        dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE}], world=world, obstacle=obstacle,
                   duration=float(duration))
        while (stop := dap.stopped())["event"] == "stopped":
            assert world_state(dap)
            dap.request("continue", {"threadId": stop["body"]["threadId"]})
    else:
        dap.launch(OBSTACLE, world=world, obstacle=obstacle, duration=float(duration))
        assert dap.stopped()["event"] == "terminated"
    summary = "".join(e["body"]["output"] for e in dap.events("output"))
    report = tmp_path / "report.json"
    out = subprocess.run([sys.executable, "-m", "rdcd_core", "simulate", str(OBSTACLE), "--world", world,
                          "--obstacle", obstacle, "--duration", duration, "--report", str(report)],
                         capture_output=True, text=True, cwd=ROOT, check=True).stdout
    if look:  # each stop names the run as the report does: the replay panel compares the two
        run = dict(dap.events("rdcd/moment")[0]["body"]["run"])
        assert run.pop("source_sha256") == hashlib.sha256(OBSTACLE.read_bytes()).hexdigest()
        reported = json.loads(report.read_text())
        assert run == {key: reported[key] for key in run} and len(run) >= 9
    significant = [line for line in out.splitlines() if line.strip() and "real time" not in line
                   and "real-time" not in line and "wall" not in line and not line.startswith("report:")]
    assert len(significant) >= 4
    missing = [line for line in significant if line not in summary]
    assert missing == []


def test_the_physics_world_handler_and_going_back_through_a_checkpoint(dap: Client) -> None:
    dap.launch(OBSTACLE, breakpoints=[{"line": HANDLER_LINE}], world="physics", obstacle="wall:0.3",
               duration=6)
    stop = run_to_handler(dap)
    thread = stop["body"]["threadId"]
    assert float(stop["body"]["description"].split("t = ")[1].split()[0]) > 2.0  # past the first checkpoint
    frame = top_frame(dap, thread)
    assert scope(dap, frame["id"], "Module")["role"] in ("LeftWheel", "RightWheel")
    dap.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": []})
    here = (stop["body"]["description"], world_state(dap))
    dap.request("next", {"threadId": thread, "granularity": "instruction"})
    ahead = (dap.stopped()["body"]["description"], world_state(dap))
    dap.request("stepBack", {"threadId": thread, "granularity": "instruction"})
    back = dap.stopped()
    assert back["body"]["description"].split(" at ")[1] == here[0].split(" at ")[1]
    assert world_state(dap) == here[1]
    dap.request("next", {"threadId": thread, "granularity": "instruction"})
    assert (dap.stopped()["body"]["description"], world_state(dap)) == ahead


def test_an_exception_breakpoint_on_a_lost_packet(dap: Client) -> None:
    dap.launch(OBSTACLE, filters=["packet"], world="lattice", packetLoss=0.3, obstacle="none", duration=5)
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["reason"] == "exception"
    assert "was lost" in stop["body"]["text"]
    sender = stop["body"]["threadId"]
    assert f"module {sender - 1}" in stop["body"]["text"]
    dap.request("setExceptionBreakpoints", {"filters": []})
    dap.request("continue", {"threadId": sender})
    assert dap.stopped()["event"] == "terminated"


GRADIENT = ROOT / "examples" / "gradient.rdcd"
GRADIENT_LINE = 16  # hops := min(neighbours.hops) + 1;


def test_the_state_scope_names_each_state_and_the_watch_reads_it(dap: Client) -> None:
    dap.launch(GRADIENT, breakpoints=[{"line": GRADIENT_LINE, "condition": "hops < 127"}],
               world="lattice", config="snake5", obstacle="none", duration=4)
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["reason"] == "breakpoint"
    frame = top_frame(dap, stop["body"]["threadId"])
    assert frame["line"] == GRADIENT_LINE
    state = scope(dap, frame["id"], "State")
    assert set(state) == {"hops"} and 0 < int(state["hops"]) < 127
    watched = dap.request("evaluate", {"expression": "hops", "frameId": frame["id"], "context": "watch"})
    assert watched["body"]["result"] == state["hops"]
    dap.request("disconnect", {"terminateDebuggee": True})


def test_the_neighbours_scope_shows_what_a_module_heard_and_the_connections(dap: Client) -> None:
    """A gradient is debugged by seeing what a module heard: each attached neighbour's published
    hops, by name, beside the module attached on that connector; the Module scope lists the
    latched connections."""
    dap.launch(GRADIENT, breakpoints=[{"line": GRADIENT_LINE, "condition": "hops < 127"}],
               world="lattice", config="snake5", obstacle="none", duration=4)
    stop = dap.stopped()
    frame = top_frame(dap, stop["body"]["threadId"])
    scopes = dap.request("scopes", {"frameId": frame["id"]})["body"]["scopes"]
    ref = next(s["variablesReference"] for s in scopes if s["name"] == "Neighbours")
    connectors = tree(dap, ref)
    attached = {name: item for name, (_, item) in connectors.items()
                if item.get("module attached", ("none", None))[0] not in ("none", "None")}
    assert attached, connectors
    heard = [item["heard"][1] for item in attached.values()]
    assert all(set(values) == {"hops"} for values in heard)
    numbers = [int(values["hops"][0]) for values in heard if values["hops"][0] not in ("none", "None")]
    assert numbers and all(0 <= n <= 127 for n in numbers), heard
    module_ref = next(s["variablesReference"] for s in scopes if s["name"] == "Module")
    connections = tree(dap, module_ref)["connections"][1]
    assert len(connections) == len(attached)
    assert all("↔ module" in value for value, _ in connections.values())
    dap.request("disconnect", {"terminateDebuggee": True})


def test_the_firmware_profile_can_be_debugged(dap: Client) -> None:
    """The original profile's controller (a port of the firmware's) cannot be copied: going back
    runs again from the start. Its runtime errors stop the world, and its lines take breakpoints."""
    dap.launch(SNAKE, filters=["runtime"], world="lattice", config="snake5", vm="original", target="default",
               obstacle="none", duration=10)
    stop = dap.stopped()
    assert stop["event"] == "stopped" and stop["body"]["reason"] == "exception", stop
    assert "unknown instruction" in stop["body"]["text"]
    thread = stop["body"]["threadId"]
    before = world_state(dap)
    dap.request("stepBack", {"threadId": thread})
    back = dap.stopped()
    assert back["event"] == "stopped" and back["body"]["reason"] == "step", (back, dap.events("output"))
    dap.request("next", {"threadId": thread})
    again = dap.stopped()
    assert again["event"] == "stopped"
    assert world_state(dap) == before
    dap.request("disconnect", {"terminateDebuggee": True})
