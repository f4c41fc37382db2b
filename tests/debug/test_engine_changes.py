"""Going back across a change of shape in the physics world: the bodies built again after a
detach do not fit the PyBullet states saved before it, so the engine starts again in a new client
and goes forward; the states it reaches are exactly those of the first time."""

from __future__ import annotations

from typing import Any

import pytest

from debug.code import CodeIndex
from debug.engine import Breakpoint, Engine, Scan, Step
from debug.inspect import Inspector, names
from debug.launch import prepare
from tests.debug.test_engine import OBSTACLE, Stops, _handler_slots, full_state


@pytest.mark.slow
def test_back_and_forward_across_a_detach_in_physics_are_the_same_states() -> None:
    launch = prepare({"program": str(OBSTACLE), "world": "physics", "obstacle": "wall:0.3",
                      "duration": 6, "changes": ["0.5s:detach 6"]})
    code = CodeIndex(launch.program, launch.methods)
    inspector = Inspector(code)
    sink = Stops()
    engine = Engine(launch.program, launch.structure, launch.options, code, sink, names)
    engine.set_breakpoints({loc: [Breakpoint(1)] for loc in code.line_locations(13)})
    try:
        engine.start(stop_on_entry=False)
        stop = sink.next()
        while stop.frame is None or stop.frame.code not in {s.code for s in _handler_slots(engine)}:
            engine.resume()
            stop = sink.next()
        engine.set_breakpoints({})
        assert engine.run is not None and engine.run.world.shape.rebuilds == 1  # past the detach
        assert 6 not in engine.run.world.robot.modules
        module = stop.module
        states = [(stop.count, full_state(engine, inspector))]
        for _ in range(2):
            engine.resume(step=Step(module, "next", True, None, 0))
            stop = sink.next()
            states.append((stop.count, full_state(engine, inspector)))

        def wanted(kind: str, runtime: Any, frame: Any) -> bool:
            return kind == "instruction" and runtime.module_id == module
        count, state = states[-2]
        engine.go_back(Scan(engine.stop.count, wanted), None)  # type: ignore[union-attr]
        stop = sink.next()
        assert stop.count == count
        assert full_state(engine, inspector) == state
        engine.resume(step=Step(module, "next", True, None, 0))
        stop = sink.next()
        assert (stop.count, full_state(engine, inspector)) == states[-1]
    finally:
        engine.terminate()
