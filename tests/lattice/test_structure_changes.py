"""Structures that change: latch, unlatch, rotate, add, remove — each checked, each a Change, the
invariants kept (no two modules in a cell, links only between facing connectors of adjacent
modules), a rotation undone by its reverse, splits that agree with a plain BFS."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sim.config import load_config, random_structure, snake
from vm import navigation
from vm.lattice.mount import Mount
from vm.lattice.structure import ModuleSpec, Structure

NS, EW, UD = navigation.NORTH_SOUTH, navigation.EAST_WEST, navigation.UP_DOWN


def bfs_parts(s: Structure) -> set[frozenset[int]]:
    adjacent: dict[int, set[int]] = {m: set() for m in s.modules}
    for link in s.links():
        adjacent[link.a].add(link.b)
        adjacent[link.b].add(link.a)
    parts, seen = set(), set()
    for m in s.modules:
        if m in seen:
            continue
        part, todo = {m}, [m]
        while todo:
            for b in adjacent[todo.pop()]:
                if b not in part:
                    part.add(b)
                    todo.append(b)
        seen |= part
        parts.add(frozenset(part))
    return parts


def test_only_a_male_connector_latches_onto_a_facing_female_one() -> None:
    s = load_config("car7")
    assert s.unlatch(0, 2).ok  # 0.2 (male) holds 1.3 (female)
    assert s.parts() == [frozenset({0, 2, 5, 6}), frozenset({1, 3, 4})]
    female = s.latch(1, 3)
    assert not female.ok and female.cause == "female"
    assert s.latch(0, 2).ok and len(s.parts()) == 1
    assert s.latch(0, 2).cause == "in_use"
    assert s.latch(0, 0).cause == "not_aligned"
    assert s.latch(0, 9).cause == "bad_connector"
    assert s.latch(42, 0).cause == "no_module"
    assert s.unlatch(1, 3).cause == "female"
    assert s.unlatch(0, 0).cause == "not_latched"
    s.check_invariants()


def test_a_quarter_turn_carries_the_moving_side_and_its_reverse_restores_it() -> None:
    s = load_config("car7")
    before = dict(s.modules)
    turn = s.rotate(1, 1)
    assert turn.ok and turn.moved == (3, 4) and turn.moving == 1
    assert s.modules[3].position != before[3].position
    s.check_invariants()
    back = s.rotate(1, -1)
    assert back.ok and s.modules == before


def test_a_loop_blocks_a_rotation() -> None:
    blocked = []
    for seed in range(40):
        s = random_structure(12, seed)
        blocked += [(seed, m) for m in s.modules if s.rotate(m, 1, apply=False).cause == "loop"]
    assert blocked
    seed, m = blocked[0]
    s = random_structure(12, seed)
    assert "loop" in s.rotate(m, 1).reason and s.version == 0


def test_the_ground_blocks_a_rotation_that_would_dig() -> None:
    s = load_config("car7")
    change = s.rotate(0, 1)
    assert not change.ok and change.cause in ("ground", "collision")
    assert s.version == 0


def test_a_turn_of_a_snake_module_moves_the_tail_and_sweeps_cells() -> None:
    s = snake(3)
    s.ground_z = None
    change = s.rotate(1, 1)
    assert change.ok
    s.check_invariants()
    s.add(ModuleSpec(9, (1, 3, 0), EW, Mount(1)))  # fails or not: either way no exception


def test_add_and_remove() -> None:
    s = snake(2)
    bad = s.add(ModuleSpec(5, (0, 0, 0), NS))
    assert bad.cause == "occupied"
    far = s.add(ModuleSpec(5, (10, 10, 10), NS))
    assert far.cause == "no_contact"
    added = s.add(ModuleSpec(5, (0, 2, 0), NS))
    assert added.ok and 5 in s.part_of(0)
    s.check_invariants()
    assert s.remove(1).ok and s.parts() == [frozenset({0}), frozenset({5})]
    assert s.remove(0).cause == "bad_place"  # the entry module defines the frame
    assert s.remove(77).cause == "no_module"


def test_listeners_hear_changes_and_snapshots_restore() -> None:
    s = load_config("car7")
    heard = []
    s.listeners.append(heard.append)
    snap = s.snapshot()
    s.unlatch(0, 2)
    s.rotate(2, 1)
    assert [c.op for c in heard if c.ok] == ["unlatch", "rotate"][:len(heard)]
    s.restore(snap)
    assert s.links() == load_config("car7").links()
    s.check_invariants()


OPS = st.lists(st.tuples(st.sampled_from(["latch", "unlatch", "rotate", "remove", "add"]),
                         st.integers(0, 11), st.integers(-3, 8)), max_size=25)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.integers(2, 14), seed=st.integers(0, 10_000), ops=OPS)
def test_random_operations_keep_the_invariants(n: int, seed: int, ops: list[tuple[str, int, int]]) -> None:
    s = random_structure(n, seed)
    for op, module, arg in ops:
        if op == "rotate":
            before = dict(s.modules)
            change = s.rotate(module, arg - 2)
            if change.ok:
                s.check_invariants()
                back = s.rotate(module, -(arg - 2), moving=change.moving)
                assert back.ok, back.reason
                assert s.modules == before
        elif op == "remove":
            change = s.remove(module)
        elif op == "add":  # next to a module, on one of its connectors' cells (free or not)
            near = s.modules.get(module) or s.modules[s.entry]
            d = s.physical_direction(near.id, arg % 8)
            cell = tuple(a + b for a, b in zip(near.position, d, strict=True))
            axis = navigation.axis_for_position(*cell)
            new = 100 + len(s.modules)
            taken = s.module_at(cell) is not None
            change = s.add(ModuleSpec(new, cell, axis or 0, Mount(arg % 4, arg % 2 == 0)))
            assert not (taken and change.ok)
            if change.ok:
                assert s.module_at(cell) == new and s.connected_channels(new)
        else:
            change = getattr(s, op)(module, arg)
        if change.ok and change.parts:
            assert set(change.parts) <= bfs_parts(s)
        s.check_invariants()
        assert set(s.parts()) == bfs_parts(s)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), quarters=st.integers(-6, 6))
def test_random_rotations_and_their_reverse(seed: int, quarters: int) -> None:
    s = random_structure(10, seed)
    for m in sorted(s.modules):
        before = dict(s.modules)
        change = s.rotate(m, quarters)
        if change.ok:
            assert s.rotate(m, -quarters, moving=change.moving).ok
            assert s.modules == before
        else:
            assert s.modules == before and change.reason
