"""The engine in process, stopped in a handler of the obstacle program, for the tests that go back
and forward (test_engine.py, test_engine_changes.py): the full state at each stop, one step over,
one step back."""

from __future__ import annotations

import queue
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from debug.code import CodeIndex
from debug.engine import Breakpoint, Engine, Goal, Scan, Sink, Step, Stop
from debug.inspect import Inspector, names
from debug.launch import prepare

ROOT = Path(__file__).resolve().parents[2]
OBSTACLE = ROOT / "examples" / "obstacle_avoidance.rdcd"
HANDLER_LINE = 13  # in the obstacle program's handler


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


def handler_slots(engine: Engine) -> list[Any]:
    assert engine.run is not None
    return [v.slot for r in engine.run.runtimes.values() for v in r.store.vectors if v is not None]


@dataclass
class Session:
    """An engine stopped in a handler: ``module`` stopped there, at ``first`` (the stop's count
    and the full state)."""

    engine: Engine
    inspector: Inspector
    sink: Stops
    module: int | None
    first: tuple[int, Any]

    def step(self) -> tuple[int, Any]:
        """One step over in ``module``; its stop's count and full state."""
        self.engine.resume(step=Step(self.module, "next", True, None, 0))
        stop = self.sink.next()
        return stop.count, full_state(self.engine, self.inspector)

    def back(self, goal: Goal | None) -> tuple[int, Any]:
        """Back to the previous instruction of ``module``; its stop's count and full state."""
        def wanted(kind: str, runtime: Any, frame: Any) -> bool:
            return kind == "instruction" and runtime.module_id == self.module

        assert self.engine.stop is not None
        self.engine.go_back(Scan(self.engine.stop.count, wanted), goal)
        stop = self.sink.next()
        return stop.count, full_state(self.engine, self.inspector)


@contextmanager
def stopped_in_a_handler(launch: dict[str, Any]) -> Iterator[Session]:
    """The obstacle program launched with ``launch`` (the debugger's launch arguments), run to the
    first stop inside a handler; breakpoints cleared; the engine ended afterwards."""
    prepared = prepare({"program": str(OBSTACLE), **launch})
    code = CodeIndex(prepared.program, prepared.methods)
    sink = Stops()
    engine = Engine(prepared.program, prepared.structure, prepared.options, code, sink, names)
    engine.set_breakpoints({loc: [Breakpoint(1)] for loc in code.line_locations(HANDLER_LINE)})
    try:
        engine.start(stop_on_entry=False)
        stop = sink.next()
        while stop.frame is None or stop.frame.code not in {s.code for s in handler_slots(engine)}:
            engine.resume()
            stop = sink.next()
        engine.set_breakpoints({})
        inspector = Inspector(code)
        yield Session(engine, inspector, sink, stop.module, (stop.count, full_state(engine, inspector)))
    finally:
        engine.terminate()
