"""Blocks in tables (docs/reconfiguration.md "Blocks in tables"): a model of the compact form's
statements with a lane — the relay's reads of S_t and S_a, and the behaviour that counts, acts
on the lane and acts on the table — run under any order of events: packets delivered late or lost, the
relay running while an action is under way, actions that fail and are tried again. Every step
must act exactly once (successfully), a block's second step never before the block has begun,
and every module must end at the number of steps."""

from __future__ import annotations

import random

from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.sequences.compact import ACT, CODES, COUNT, LANE

# the statements this model runs, as the compiler writes them (in the order COUNT, LANE, ACT)
assert COUNT.startswith("if ({d} == 1 && {t} > 0)") and "{t} := 0; {d} := 0;" in COUNT
assert LANE == "if ({d} == 0) {{ if (self.act({a})) {{ {d} := 1; {t} := 0; }} }}"
assert "{t} := 0; }" in ACT


class Module:
    def __init__(self, key: int) -> None:
        self.key = key
        self.s = self.t = self.a = self.par = 0
        self.heard: dict[int, int] = {}
        self.run = None  # the behaviour's run under way (a generator), if any


def read(entries: dict[int, int], value: int, key: int) -> int:
    return entries.get(value, 0) - key * CODES


def behaviour(m: Module, lane: dict[int, int], log: list, fail: random.Random,
              p_fail: float):  # noqa: ANN201 - generator
    """One run of the behaviour that acts; yields while an action is under way."""

    def act(code: int, source: str):  # noqa: ANN202 - generator: True when the action succeeded
        if not 1 <= code < CODES:
            return False
        at = m.s
        log.append(("start", m.key, code, at, source))
        yield
        ok = fail.random() >= p_fail
        log.append(("end" if ok else "failed", m.key, code, at, source))
        return ok

    if m.par == 1 and m.t > 0:  # COUNT: the lane's step, at its own value
        m.s, m.t, m.par = m.s + 1, 0, 0
    if m.par == 0:  # LANE
        if (yield from act(m.a, "lane")):
            m.par, m.t = 1, 0
    if (yield from act(m.t, "table")):  # ACT
        m.s, m.t = m.s + 1, 0


def simulate(keys: list[int], steps: list[tuple[int, int]], blocks: list[int], edges: list[tuple[int, int]],
             order: random.Random, loss: float, p_fail: float) -> tuple[list[Module], list]:
    """``steps``: (key, code) in the order they are counted, a block's smaller key first
    (compact.count_order); ``blocks``: the first value of each block of two (its second step may
    act from there: the lane holds its code at that value)."""
    main = {v: key * CODES + code for v, (key, code) in enumerate(steps)}
    lane = {}
    for b in blocks:
        assert steps[b][0] < steps[b + 1][0]
        key, code = steps[b + 1]
        lane[b] = key * CODES + code
    modules = [Module(k) for k in keys]
    links = [(a, b) for a, b in edges] + [(b, a) for a, b in edges]
    log: list = []
    for _ in range(60000):
        if all(m.s == len(steps) and m.run is None for m in modules):
            break
        kind = order.random()
        if kind < 0.35:  # a published value travels, or is lost (sent again later)
            a, b = order.choice(links)
            if order.random() >= loss:
                modules[b].heard[a] = modules[a].s
        elif kind < 0.65:  # the relay: max, then the reads
            m = order.choice(modules)
            m.s = max([m.s, *m.heard.values()])
            m.t, m.a = read(main, m.s, m.key), read(lane, m.s, m.key)
        else:  # the behaviour that acts: a new run, or the one under way goes on
            m = order.choice(modules)
            if m.run is None:
                m.run = behaviour(m, lane, log, order, p_fail)
            try:
                next(m.run)
            except StopIteration:
                m.run = None
    return modules, log


@settings(max_examples=150, deadline=None)
@given(st.integers(2, 7), st.integers(2, 9), st.integers(0, 10**6),
       st.sampled_from([0.0, 0.3, 0.6]), st.sampled_from([0.0, 0.3]))
def test_every_step_acts_once_and_is_counted_in_order(n: int, length: int, seed: int, loss: float,
                                                      p_fail: float) -> None:
    order = random.Random(seed)
    keys = order.sample(range(9), n)  # one key a module (the compact form's E811)
    edges = [(k, order.randrange(k)) for k in range(1, n)]  # a random tree: connected
    steps = [(order.choice(keys), order.choice([1, 2, 5, 6, 9, 10, 12, 13])) for _ in range(length)]
    blocks: list[int] = []
    v = 0
    while v + 1 < length:  # blocks of two steps of different modules (E816), not overlapping
        if steps[v][0] != steps[v + 1][0] and order.random() < 0.5:
            if steps[v][0] > steps[v + 1][0]:  # counted smaller key first (count_order)
                steps[v], steps[v + 1] = steps[v + 1], steps[v]
            blocks.append(v)
            v += 2
        else:
            v += 1
    modules, log = simulate(keys, steps, blocks, edges, order, loss, p_fail)
    assert [m.s for m in modules] == [length] * n

    def step(key: int, code: int, at: int, source: str) -> int:
        """Which step an action is: the table's at the progress, the lane's its block's second."""
        number = at if source == "table" else at + 1
        assert steps[number] == (key, code), (key, code, at, source)  # the acting module's own
        return number

    done = sorted(step(*entry[1:]) for entry in log if entry[0] == "end")
    assert done == list(range(length))  # each step's action succeeded exactly once
    for entry in log:  # and none acted before its stage began: a lane's from its block's start
        if entry[0] == "start":
            number = step(*entry[1:])
            assert entry[3] >= (number - 1 if number - 1 in blocks else number)


def test_a_block_lets_its_second_step_act_before_the_first_is_counted() -> None:
    keys, steps = [0, 1, 2], [(0, 9), (1, 9), (2, 5)]
    overlapped = 0
    for seed in range(40):
        _, log = simulate(keys, steps, [0], [(0, 1), (1, 2)], random.Random(seed), 0.0, 0.0)
        starts = {entry[1]: entry[3] for entry in log if entry[0] == "start"}
        overlapped += starts[1] == 0  # module 1 started step 1 while the progress it had was 0
    assert overlapped > 0
