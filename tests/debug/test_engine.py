"""The engine in process: going back to a moment and forward again gives exactly the same full
states (every module's scopes, its random generator, the joints unrounded, the bodies' poses)."""

from __future__ import annotations

import queue
from pathlib import Path
from typing import Any

import pytest

from debug.code import CodeIndex
from debug.engine import Breakpoint, Engine, Goal, Scan, Sink, Step, Stop
from debug.inspect import Inspector, names
from debug.launch import prepare

ROOT = Path(__file__).resolve().parents[2]
OBSTACLE = ROOT / "examples" / "obstacle_avoidance.rdcd"


class Stops(Sink):
    def __init__(self) -> None:
        self.q: queue.Queue[Any] = queue.Queue()

    def stopped(self, stop: Stop) -> None:
        self.q.put(stop)

    def ended(self, run: Any) -> None:
        self.q.put("ended")

    def failed(self, message: str) -> None:
        self.q.put(message)

    def next(self) -> Stop:
        item = self.q.get(timeout=120)
        assert isinstance(item, Stop), item
        return item


def full_state(engine: Engine, inspector: Inspector) -> Any:
    run = engine.run
    assert run is not None
    state: dict[str, Any] = {"time": run.time, "count": engine.count}
    for mid, runtime in run.runtimes.items():
        hal = runtime.hal
        state[mid] = (inspector.full_state(runtime, run), hal.joint_angle_deg(), hal.joint_turns())
    if hasattr(run.world, "module_centres"):
        state["centres"] = {mid: tuple(c) for mid, c in run.world.module_centres().items()}
    return state


@pytest.mark.parametrize(("world", "obstacle"), [("lattice", "wall:0.1"), ("physics", "wall:0.3")])
def test_back_and_forward_again_are_the_same_states(world: str, obstacle: str) -> None:
    launch = prepare({"program": str(OBSTACLE), "world": world, "obstacle": obstacle, "duration": 6})
    code = CodeIndex(launch.program, launch.methods)
    inspector = Inspector(code)
    sink = Stops()
    engine = Engine(launch.program, launch.structure, launch.options, code, sink, names)
    handler_line = 13
    engine.set_breakpoints({loc: [Breakpoint(1)] for loc in code.line_locations(handler_line)})
    try:
        engine.start(stop_on_entry=False)
        stop = sink.next()
        while stop.frame is None or stop.frame.code not in {s.code for s in _handler_slots(engine)}:
            engine.resume()
            stop = sink.next()
        engine.set_breakpoints({})
        module = stop.module
        states = [(stop.count, full_state(engine, inspector))]
        for _ in range(4):
            engine.resume(step=Step(module, "next", True, None, 0))
            stop = sink.next()
            states.append((stop.count, full_state(engine, inspector)))
        assert len({repr(s) for _, s in states}) == 5
        for count, state in reversed(states[:-1]):
            def wanted(kind: str, runtime: Any, frame: Any) -> bool:
                return kind == "instruction" and runtime.module_id == module
            engine.go_back(Scan(engine.stop.count, wanted), Goal(0, "step"))  # type: ignore[union-attr]
            stop = sink.next()
            assert stop.count == count
            assert full_state(engine, inspector) == state
        for count, state in states[1:]:
            engine.resume(step=Step(module, "next", True, None, 0))
            stop = sink.next()
            assert (stop.count, full_state(engine, inspector)) == (count, state)
    finally:
        engine.terminate()


def _handler_slots(engine: Engine) -> list[Any]:
    assert engine.run is not None
    return [v.slot for r in engine.run.runtimes.values() for v in r.store.vectors if v is not None]


def test_a_pause_while_stopped_does_nothing_and_one_right_after_continue_is_kept() -> None:
    """A pause asked while the world is stopped (and not told to go on) is not kept for later: the
    next stop is the breakpoint. A continue then a pause before the world's thread has woken
    stops the world (the session used to drop such a pause, and the run went on to its end)."""
    launch = prepare({"program": str(OBSTACLE), "world": "lattice", "obstacle": "none", "duration": 3000})
    code = CodeIndex(launch.program, launch.methods)
    sink = Stops()
    engine = Engine(launch.program, launch.structure, launch.options, code, sink, names)
    engine.set_breakpoints({loc: [Breakpoint(1)] for loc in code.line_locations(12)})  # startup move()
    try:
        engine.start(stop_on_entry=True)
        assert sink.next().reason == "entry"
        engine.pause()  # stopped, not told to go on: nothing to pause
        engine.resume()
        assert sink.next().reason == "breakpoint"
        engine.set_breakpoints({})
        with engine._cv:  # hold the world's thread asleep while both requests arrive
            engine.resume()
            engine.pause()
        stop = sink.next()
        assert stop.reason == "pause" and stop.time < 3000
    finally:
        engine.terminate()
