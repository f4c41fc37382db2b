"""The engine in process: going back to a moment and forward again gives exactly the same full
states (every module's scopes, its random generator, the joints unrounded, the bodies' poses)."""

from __future__ import annotations

import pytest

from debug.code import CodeIndex
from debug.engine import Breakpoint, Engine, Goal
from debug.inspect import names
from debug.launch import prepare
from tests.debug.engine_session import OBSTACLE, Stops, stopped_in_a_handler


@pytest.mark.parametrize(("world", "obstacle"), [("lattice", "wall:0.1"), ("physics", "wall:0.3")])
def test_back_and_forward_again_are_the_same_states(world: str, obstacle: str) -> None:
    with stopped_in_a_handler({"world": world, "obstacle": obstacle, "duration": 6}) as session:
        states = [session.first] + [session.step() for _ in range(4)]
        assert len({repr(s) for _, s in states}) == 5
        for count_state in reversed(states[:-1]):
            assert session.back(Goal(0, "step")) == count_state
        for count_state in states[1:]:
            assert session.step() == count_state


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
