"""No sequence takes car7 to a straight snake of seven lying flat (docs/reconfiguration.md "car7
into a snake"), which is why car_to_snake ends in a bent chain and no straight snake's gait
follows it.

A straight snake that keeps car7's axle-wheel links is wheel-axle-wheel-driver-wheel-axle-wheel:
each axle has both wheels on one hemisphere, so the axles (and the driver between the triples)
sit beside the spine of wheels. From each of its eight side patterns, everything the lattice model
can do (``vm.lattice.plan.moves``: every latch, every unlatch that does not split the robot, every
quarter or half turn with the moving side a sequence gets) reaches nine shapes only, none of them
car7's. Read backwards, a sequence from car7 to such a snake would reach car7 from it, so there is
none (the half turns and both signs of a turn are in ``moves``, so the undo of every turn is too).
"""

from __future__ import annotations

import itertools

import pytest

from sim.config import load_config
from vm import navigation
from vm.lattice.plan import canonical, moves
from vm.lattice.structure import ModuleSpec, Structure, make_structure

ORDER = [3, 1, 4, 0, 5, 2, 6]  # wheel, axle, wheel, driver, wheel, axle, wheel (car7's ids)


def _snake(sides: tuple[int, int, int]) -> Structure:
    """The straight snake along y: wheels on the spine x = 0, each axle and the driver at x = ±1;
    the middle wheel of the first triple (module 4) at the origin, the entry."""
    specs = []
    for i, m in enumerate(ORDER):
        place = (0 if i % 2 == 0 else sides[i // 2], i - 2, 0)
        specs.append(ModuleSpec(m, place, navigation.axis_for_position(*place)))
    specs.sort(key=lambda s: s.id != 4)
    return make_structure(specs, entry=4)


def _shape(s: Structure) -> tuple:
    return (tuple(sorted((m, spec.position) for m, spec in s.modules.items())),
            tuple(sorted((k.a, k.b) for k in s.links())))


def _reachable(start: Structure) -> list[Structure]:
    seen = {_shape(start): start.copy()}
    todo = [start.snapshot()]
    s = start.copy()
    while todo:
        snap = todo.pop()
        s.restore(snap)
        for op in moves(s):
            s.restore(snap)
            op.apply(s)
            if _shape(s) not in seen:
                seen[_shape(s)] = s.copy()
                todo.append(s.snapshot())
    return list(seen.values())


@pytest.mark.parametrize("sides", list(itertools.product((1, -1), repeat=3)))
def test_from_a_straight_snake_nine_shapes_are_reachable_and_car7_is_not_one(sides) -> None:  # noqa: ANN001
    snake = _snake(sides)
    chain = {frozenset((k.a, k.b)) for k in snake.links()}
    assert len(chain) == 6 and {frozenset((1, 3)), frozenset((1, 4)), frozenset((2, 5)),
                                frozenset((2, 6))} <= chain  # car7's axle-wheel links kept
    found = _reachable(snake)
    assert len(found) == 9
    car = {canonical(load_config("car7"), k) for k in range(4)}
    for s in found:
        assert {frozenset((k.a, k.b)) for k in s.links()} == chain  # no latch ever closes
        assert max(spec.position[2] for spec in s.modules.values()) <= 1  # car7's driver is 2 up
        assert canonical(s) not in car
