"""gc_paused: the front end's pause of the cyclic collector."""

from __future__ import annotations

import gc
import weakref

from rdcd_core.gcpause import gc_paused


class _Node:
    def __init__(self) -> None:
        self.me = self  # a cycle: only the collector frees it


def test_the_collector_is_restored_and_pauses_nest() -> None:
    assert gc.isenabled()
    with gc_paused():
        assert not gc.isenabled()
        with gc_paused():
            assert not gc.isenabled()
        assert not gc.isenabled()  # the inner pause does not end the outer one
    assert gc.isenabled()


def test_a_disabled_collector_stays_disabled() -> None:
    gc.disable()
    try:
        with gc_paused():
            pass
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_what_the_block_made_goes_to_the_oldest_generation_and_cycles_are_still_freed() -> None:
    with gc_paused():
        made = [[index] for index in range(1000)]
        cycle = _Node()
    oldest = {id(x) for x in gc.get_objects(generation=2)}
    assert id(made) in oldest and id(made[500]) in oldest and id(cycle) in oldest
    assert not any(x is made for x in gc.get_objects(generation=0))  # no young scan of the tree
    watch = weakref.ref(cycle)
    del cycle
    gc.collect()
    assert watch() is None
