"""Going back across a change of shape in the physics world: the bodies built again after a
detach do not fit the PyBullet states saved before it, so the engine starts again in a new client
and goes forward; the states it reaches are exactly those of the first time."""

from __future__ import annotations

import pytest

from tests.debug.engine_session import stopped_in_a_handler


@pytest.mark.slow
def test_back_and_forward_across_a_detach_in_physics_are_the_same_states() -> None:
    launch = {"world": "physics", "obstacle": "wall:0.3", "duration": 6, "changes": ["0.5s:detach 6"]}
    with stopped_in_a_handler(launch) as session:
        run = session.engine.run
        assert run is not None and run.world.shape.rebuilds == 1  # past the detach
        assert 6 not in run.world.robot.modules
        states = [session.first] + [session.step() for _ in range(2)]
        assert session.back(None) == states[-2]
        assert session.step() == states[-1]
