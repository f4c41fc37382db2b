"""The debugger's launch option "changes": outside changes checked as rdcd simulate checks them."""

from __future__ import annotations

import pytest

from debug.launch import LaunchError, prepare


def launch(changes: object) -> dict:
    return {"program": "examples/lose_a_wheel.rdcd", "world": "lattice", "duration": 30,
            "obstacle": "none", "changes": changes}


def test_changes_reach_the_run_options() -> None:
    prepared = prepare(launch(["20s:detach 3", "25s:stop 5"]))
    assert [c.kind for c in prepared.options.outside_changes] == ["detach", "stop"]


@pytest.mark.parametrize(("changes", "words"), [
    ("20s:detach 3", "list of strings"),
    ([3], "list of strings"),
    (["20s:detach 33"], "no module 33"),
    (["99s:detach 3"], "after the end"),
    (["nonsense"], "TIME:detach ID"),
])
def test_bad_changes_are_launch_errors(changes: object, words: str) -> None:
    with pytest.raises(LaunchError, match=words):
        prepare(launch(changes))
