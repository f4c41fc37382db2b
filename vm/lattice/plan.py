"""A planner that finds a reconfiguration sequence in the lattice model: the latches, unlatches and
quarter turns (``vm.lattice.changes``) that take a start structure to the shape of a target, up to
a translation and a quarter turn about the vertical axis (docs/reconfiguration.md "Finding a
sequence").

Search: best-first (weighted A*) over states of a ``Structure`` (``snapshot``/``restore``), one
operation per edge, each checked by the structure's own operations, so a plan is exactly what the
lattice world and ``rdcd check`` do. A quarter turn is ``rotate(m, q)`` with the default choice of
the moving hemisphere, since a sequence's ``turnQuarters(n)`` cannot choose it. The space is cut
down by: never splitting the robot (a split unlatch is not an edge), one state per shape (cells,
orientations, joints and links; module identities kept, since roles are tied to modules), a bound
on the number of operations (``max_steps``) and on the states expanded (``max_states``). The
heuristic is not admissible (the plan is short, not always the shortest): the difference between
the sorted heights of the modules and the target's, the difference of the sorted pairwise
distances (both invariant under the symmetries), and the target links still open.

Errors are values: ``plan`` never raises on a bad target; it returns a ``Plan`` with ``ok`` False
and a one-line ``reason``.
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

from vm import navigation
from vm.lattice.structure import Snapshot, Structure

Vec = tuple[int, int, int]
EW, NS, UD = navigation.EAST_WEST, navigation.NORTH_SOUTH, navigation.UP_DOWN
_TURNED_AXIS = {EW: NS, NS: EW, UD: UD}  # a quarter turn about z swaps the horizontal axes
TURNS = (1, -1, 2)  # quarter turns tried per module (3 ends where -1 does, by a longer sweep)


@dataclass(frozen=True)
class Op:
    """One step: ``kind`` latch | unlatch | rotate; ``arg`` the physical connector or quarters."""

    kind: str
    module: int
    arg: int

    def apply(self, s: Structure) -> object:
        if self.kind == "latch":
            return s.latch(self.module, self.arg)
        if self.kind == "unlatch":
            return s.unlatch(self.module, self.arg)
        return s.rotate(self.module, self.arg)

    def inverse(self) -> Op:
        kind = {"latch": "unlatch", "unlatch": "latch", "rotate": "rotate"}[self.kind]
        return Op(kind, self.module, -self.arg if self.kind == "rotate" else self.arg)

    def text(self) -> str:
        action = {"latch": "connect", "unlatch": "disconnect", "rotate": "turnQuarters"}[self.kind]
        return f"{action}({self.arg})"


@dataclass
class Plan:
    ok: bool
    ops: list[Op] = field(default_factory=list)
    reason: str = ""
    expanded: int = 0  # states taken from the queue
    final: Structure | None = None  # the structure after the plan (a copy)


# ---- shapes up to the symmetries -------------------------------------------------------------
def _turn(p: Vec, k: int) -> Vec:
    x, y, z = p
    for _ in range(k % 4):
        x, y = -y, x
    return (x, y, z)


def _cells(s: Structure) -> dict[int, tuple[Vec, int]]:
    return {m: (spec.position, spec.axis) for m, spec in s.modules.items()}


def _link_cells(s: Structure) -> list[tuple[Vec, Vec]]:
    return [(s.modules[k.a].position, s.modules[k.b].position) for k in s.links()]


def canonical(s: Structure, k: int = 0) -> tuple[frozenset, frozenset]:
    """Cells with axes and links as cell pairs, turned ``k`` quarters about z and moved so that the
    smallest cell is at the origin: equal for two structures of one shape (same turn)."""
    turned = {m: (_turn(p, k), _TURNED_AXIS[a] if k % 2 else a) for m, (p, a) in _cells(s).items()}
    low = min(p for p, _ in turned.values())

    def moved(p: Vec) -> Vec:
        return (p[0] - low[0], p[1] - low[1], p[2] - low[2])

    cells = frozenset((moved(p), a) for p, a in turned.values())
    links = frozenset(frozenset((moved(_turn(a, k)), moved(_turn(b, k)))) for a, b in _link_cells(s))
    return cells, links


class Goal:
    """The shape of ``target`` in any of its four turns about z and any translation; with
    ``grounded`` the lowest module must rest on the start's ground."""

    def __init__(self, target: Structure, grounded: bool = True) -> None:
        self.target = target
        self.forms = {canonical(target, k) for k in range(4)}
        self.size = len(target.modules)
        self.grounded = grounded
        self.heights = sorted(p[2] - min(q[2] for q, _ in _cells(target).values())
                              for p, _ in _cells(target).values())
        self.links = len(target.links())
        self.places: list[list[tuple[Vec, int]]] = []

    def aim(self, start: Structure, keep: int = 4) -> None:
        """Choose the placements the estimate measures against: the turns and translations of the
        target, resting on the start's ground, that keep the most modules of ``start`` where they
        are (cell and axis) — reconfiguring moves as little as it can."""
        cells = set(_cells(start).values())
        ground = start.ground_z if start.ground_z is not None else min(p[2] for p, _ in cells)
        xs = [p[0] for p, _ in cells]
        ys = [p[1] for p, _ in cells]
        scored = []
        for k in range(4):
            turned = [(_turn(p, k), _TURNED_AXIS[a] if k % 2 else a) for p, a in _cells(self.target).values()]
            low = min(p[2] for p, _ in turned)
            for dx in range(min(xs) - 4, max(xs) + 5):
                for dy in range(min(ys) - 4, max(ys) + 5):
                    place = [((p[0] + dx, p[1] + dy, p[2] - low + ground), a) for p, a in turned]
                    if all(navigation.axis_for_position(*p) == a for p, a in place):
                        scored.append((-len(cells & set(place)), k, dx, dy, place))
        scored.sort(key=lambda t: t[:4])
        self.places = [t[4] for t in scored[:keep]]

    def reached(self, s: Structure) -> bool:
        if len(s.modules) != self.size or canonical(s) not in self.forms:
            return False
        return not self.grounded or s.ground_z is None or \
            min(spec.position[2] for spec in s.modules.values()) == s.ground_z

    def estimate(self, s: Structure) -> float:
        """Lattice steps of the cheapest assignment of modules to the target's cells (in the best
        placement; a cell of another axis costs one more), plus half a step for every link to make
        or open. Not admissible: a quarter turn moves several modules at once."""
        cells = list(_cells(s).values())
        if self.places:
            h = min(_assignment([[(abs(p[0] - q[0]) + abs(p[1] - q[1]) + abs(p[2] - q[2])) // 2
                                  + (a != b) for q, b in cells] for p, a in place])
                    for place in self.places)
        else:
            ground = s.ground_z if s.ground_z is not None else min(p[2] for p, _ in cells)
            heights = sorted(p[2] - ground for p, _ in cells)
            h = sum(abs(a - b) for a, b in zip(heights, self.heights, strict=False))
        return h + 0.5 * abs(len(s.links()) - self.links)


class FlatChain:
    """Any chain of the modules (each latched to at most two, no loop) lying flat on the ground:
    a snake of any bend. ``finish`` makes the chain's links from what is latched or can latch."""

    places: list = []

    def __init__(self, size: int, reversible: bool = True) -> None:
        self.size = size
        self.reversible = reversible  # never open a link of one sex (see ``macros``)

    def aim(self, start: Structure) -> None:
        return None

    def reached(self, s: Structure) -> bool:
        if len(s.modules) != self.size or not _flat(s):
            return False
        links = s.links()
        degree: dict[int, int] = {}
        for k in links:
            degree[k.a] = degree.get(k.a, 0) + 1
            degree[k.b] = degree.get(k.b, 0) + 1
        return len(links) == self.size - 1 and max(degree.values(), default=0) <= 2 and \
            len(s.parts()) == 1

    def estimate(self, s: Structure) -> float:
        ground = s.ground_z if s.ground_z is not None else min(x.position[2] for x in s.modules.values())
        return float(sum(spec.position[2] - ground for spec in s.modules.values()))

    def finish(self, s: Structure) -> list[Op] | None:
        """On a flat structure: latch and unlatch so that the links are one chain through every
        module (found over latched and latchable pairs), or None."""
        if not _flat(s):
            return None
        pairs: dict[frozenset[int], Op | None] = {
            frozenset((k.a, k.b)): None for k in s.links()}
        for op in latches(s):
            other = s.facing(op.module, op.arg)
            if other is not None:
                pairs.setdefault(frozenset((op.module, other[0])), op)
        path = _chain(sorted(s.modules), pairs)
        if path is None:
            return None
        used = {frozenset(p) for p in zip(path, path[1:], strict=False)}
        ops = [op for pair, op in pairs.items() if pair in used and op is not None]
        extra = [k for k in s.links() if frozenset((k.a, k.b)) not in used]
        if self.reversible and any((k.a_physical + k.b_physical) % 2 == 0 for k in extra):
            return None  # a link of one sex would have to open (see ``macros``)
        ops += [_opener((k.a, k.a_physical, k.b, k.b_physical)) for k in extra]
        snap = s.snapshot()
        if all(_whole(op.apply(s)) for op in ops) and self.reached(s):
            return ops
        s.restore(snap)
        return None


def _flat(s: Structure) -> bool:
    ground = s.ground_z if s.ground_z is not None else min(x.position[2] for x in s.modules.values())
    return all(spec.position[2] == ground for spec in s.modules.values())


def _chain(nodes: list[int], pairs: dict) -> list[int] | None:
    """A path through every node over ``pairs`` (depth-first; a handful of modules)."""
    near: dict[int, list[int]] = {n: [] for n in nodes}
    for pair in pairs:
        a, b = sorted(pair)
        near[a].append(b)
        near[b].append(a)

    def grow(path: list[int]) -> list[int] | None:
        if len(path) == len(nodes):
            return path
        for n in sorted(near[path[-1]]):
            if n not in path:
                found = grow([*path, n])
                if found:
                    return found
        return None

    for first in sorted(nodes, key=lambda n: len(near[n])):
        found = grow([first])
        if found:
            return found
    return None


def _assignment(cost: list[list[int]]) -> int:
    """The least total cost of a one-to-one assignment of rows to columns (square matrix):
    the Hungarian method, O(n^3)."""
    n = len(cost)
    inf = float("inf")
    u, v = [0.0] * (n + 1), [0.0] * (n + 1)
    match, way = [0] * (n + 1), [0] * (n + 1)
    for i in range(1, n + 1):
        match[0] = i
        j0 = 0
        low = [inf] * (n + 1)
        used = [False] * (n + 1)
        while True:
            used[j0] = True
            i0, delta, j1 = match[j0], inf, 0
            for j in range(1, n + 1):
                if not used[j]:
                    c = cost[i0 - 1][j - 1] - u[i0] - v[j]
                    if c < low[j]:
                        low[j], way[j] = c, j0
                    if low[j] < delta:
                        delta, j1 = low[j], j
            for j in range(n + 1):
                if used[j]:
                    u[match[j]] += delta
                    v[j] -= delta
                else:
                    low[j] -= delta
            j0 = j1
            if match[j0] == 0:
                break
        while j0:
            j1 = way[j0]
            match[j0] = match[j1]
            j0 = j1
    return int(round(sum(cost[match[j] - 1][j - 1] for j in range(1, n + 1))))


def _pairwise(s: Structure) -> list[int]:
    cells = [spec.position for spec in s.modules.values()]
    return sorted(sum(abs(a - b) for a, b in zip(p, q, strict=True)) // 2
                  for p, q in itertools.combinations(cells, 2))


def _axis_counts(s: Structure) -> dict[int, int]:
    out = {EW: 0, NS: 0, UD: 0}
    for spec in s.modules.values():
        out[spec.axis] += 1
    return out


# ---- the search ------------------------------------------------------------------------------
def _key(s: Structure) -> tuple:
    return (tuple(sorted((m, spec.position, spec.axis, spec.mount.rotation, spec.mount.mirrored,
                          spec.joint % 4) for m, spec in s.modules.items())),
            tuple((k.a, k.a_physical, k.b, k.b_physical) for k in s.links()))


def moves(s: Structure, turns: Iterable[int] = TURNS) -> list[Op]:
    """Every operation that can happen on ``s`` without splitting it (not applied)."""
    out: list[Op] = []
    for m in sorted(s.modules):
        ports = s.neighbours(m)
        out.extend(_latches_of(s, m, ports))
        for p, (b, pb) in sorted(ports.items()):
            if p % 2 == 0 or pb % 2:  # the male end opens it (either end of a same-sex link)
                snap = s.snapshot()
                change = s.unlatch(m, p)
                whole = change.ok and not change.parts
                s.restore(snap)
                if whole and not (p % 2 and pb % 2 and b < m):
                    out.append(Op("unlatch", m, p))
        for q in turns:
            if s.rotate(m, q, apply=False).ok:
                out.append(Op("rotate", m, q))
    return out


def latches(s: Structure) -> list[Op]:
    """Every latch that can close on ``s``: a free male connector facing a free female one."""
    return [op for m in sorted(s.modules) for op in _latches_of(s, m, s.neighbours(m))]


def _latches_of(s: Structure, m: int, ports: dict) -> list[Op]:
    """The latches module ``m`` (latched at ``ports``) can close: a free male connector of its
    facing a free female one."""
    out = []
    for p in (0, 2, 4, 6):
        if p not in ports:
            other = s.facing(m, p)
            if other is not None and other[1] % 2 and other[1] not in s.neighbours(other[0]):
                out.append(Op("latch", m, p))
    return out


def _opener(link: tuple[int, int, int, int]) -> Op:
    a, pa, b, pb = link
    return Op("unlatch", a, pa) if pa % 2 == 0 else Op("unlatch", b, pb)


def macros(s: Structure, turns: Iterable[int] = TURNS, max_cut: int = 2,
           keep_entry: bool = True, reversible: bool = True) -> list[list[Op]]:
    """Macro-steps on ``s`` (restored afterwards): a quarter turn with the fewest unlatches before
    it that let it happen without splitting the robot (at most ``max_cut``; a cut is minimal: no
    smaller cut found for the same turn is part of it), each once without and once with every
    latch that can close after it. ``keep_entry``: no turn carries the entry module (it defines
    the frame a module learns its coordinates in; the modules keep what they learned in the start,
    forward and backwards, but one that learned its place afresh would learn it in a moved frame)."""
    snap = s.snapshot()
    # ``reversible``: a link between two connectors of one sex (a configuration's) never opens:
    # it could not close again, and the sequence could not be run backwards
    links = _openable(s, reversible)
    out: list[list[Op]] = []
    for m in sorted(s.modules):
        for q in turns:
            for ops in _minimal_cuts(s, snap, links, m, q, max_cut):
                if s.entry in s.rotate(m, q).moved and keep_entry:
                    continue
                ops.append(Op("rotate", m, q))
                out.append(ops)
                after = latches(s)
                if after:
                    out.append(ops + after)
    s.restore(snap)
    return out


def _openable(s: Structure, reversible: bool) -> list[tuple[int, int, int, int]]:
    """The links a step may open; ``reversible``: not one between two connectors of one sex."""
    return [(k.a, k.a_physical, k.b, k.b_physical) for k in s.links()
            if not reversible or (k.a_physical + k.b_physical) % 2]


def _minimal_cuts(s: Structure, base: Snapshot, links: list[tuple[int, int, int, int]], m: int,
                  q: int, max_cut: int) -> Iterator[list[Op]]:
    """The unlatches of each minimal cut (at most ``max_cut`` of ``links``; no smaller cut found
    is part of it) that lets ``m`` turn by ``q`` without splitting the robot; when one is yielded,
    ``s`` is ``base`` with the cut opened and the turn not made yet."""
    cuts: list[set] = []
    for r in range(max_cut + 1):
        for subset in itertools.combinations(links, r):
            if any(c <= set(subset) for c in cuts):
                continue
            s.restore(base)
            ops = [_opener(link) for link in subset]
            if not all(_whole(op.apply(s)) for op in ops) or not s.rotate(m, q, apply=False).ok:
                continue
            cuts.append(set(subset))
            yield ops


def _whole(change: object) -> bool:
    return bool(getattr(change, "ok", False)) and not getattr(change, "parts", ())


def plan(start: Structure, target: Structure | Goal | FlatChain, *, max_steps: int = 30,
         max_states: int = 2000, weight: float = 2.0, max_cut: int = 2,
         actor_cost: float = 0.0, avoid: frozenset[int] = frozenset(),
         keep_entry: bool = True, reversible: bool = True) -> Plan:
    """The operations that take ``start`` to the shape of ``target`` (see the module's doc), or a
    Plan with ``ok`` False and why. The search runs over macro-steps (``macros``); a state whose
    cells are the target's is finished by every latch that can close. ``actor_cost``: added for
    every module that acts for the first time (each acting module costs a role, and a role a
    program fragment); ``avoid``: modules that never act (the entry, say); ``keep_entry`` and
    ``reversible``: see ``macros`` (a ``FlatChain`` target has its own ``reversible``)."""
    try:
        goal = target if isinstance(target, (Goal, FlatChain)) else Goal(target)
    except (AttributeError, TypeError, ValueError, KeyError) as error:
        return Plan(False, reason=f"not a target structure: {error}")
    if not isinstance(start, Structure):
        return Plan(False, reason="not a start structure")
    if goal.size != len(start.modules):
        return Plan(False, reason=f"the target has {goal.size} modules, the start "
                    f"{len(start.modules)}")
    s = start.copy()
    if not goal.places:
        goal.aim(s)
    counter = itertools.count()
    queue = [(goal.estimate(s) * weight, next(counter), 0, s.snapshot(), ())]
    seen = {_key(s): 0}
    expanded = 0
    while queue:
        _, _, g, snap, ops = heapq.heappop(queue)
        s.restore(snap)
        done = _finish(s, goal)
        if done is not None:
            return Plan(True, [*ops, *done], expanded=expanded, final=s.copy())
        expanded += 1
        if expanded > max_states:
            return Plan(False, reason=f"no sequence found within {max_states} states "
                        f"(at most {max_steps} steps)", expanded=expanded - 1)
        actors = {op.module for op in ops}
        for macro in macros(s, max_cut=max_cut, keep_entry=keep_entry, reversible=reversible):
            if g + len(macro) > max_steps or any(op.module in avoid for op in macro):
                continue
            cost = len(macro) + actor_cost * len({op.module for op in macro} - actors)
            s.restore(snap)
            for op in macro:
                op.apply(s)
            key = _key(s)
            if seen.get(key, float("inf")) <= g + cost:
                continue
            seen[key] = g + cost
            heapq.heappush(queue, (g + cost + weight * goal.estimate(s), next(counter),
                                   g + cost, s.snapshot(), (*ops, *macro)))
    return Plan(False, reason=f"no sequence within {max_steps} steps", expanded=expanded)


def _finish(s: Structure, goal: Goal | FlatChain) -> list[Op] | None:
    """When the cells are the target's: the latches that close the target's links (applied), or
    None (``s`` unchanged) when the cells or the links cannot be the target's."""
    if goal.reached(s):
        return []
    if isinstance(goal, FlatChain):
        return goal.finish(s)
    cells = canonical(s)[0]
    if not any(cells == form[0] for form in goal.forms):
        return None
    snap = s.snapshot()
    ops = latches(s)
    for op in ops:
        op.apply(s)
    if goal.reached(s):
        return ops
    s.restore(snap)
    return None


def replay(start: Structure, ops: Iterable[Op]) -> Structure:
    """A copy of ``start`` after ``ops``; ValueError (one line) at the first that cannot happen."""
    s = start.copy()
    for i, op in enumerate(ops):
        change = op.apply(s)
        if not getattr(change, "ok", False):
            raise ValueError(f"step {i + 1} ({op.kind} {op.module} {op.arg}): "
                             f"{getattr(change, 'reason', '')}")
    return s


# ---- a search guided by a known sequence's actors ---------------------------------------------
def _turn_steps(s: Structure, m: int, q: int, max_cut: int, reversible: bool,
                early_latches: bool = False) -> list[list[Op]]:
    """The ways one quarter turn of ``m`` by ``q`` can happen on ``s`` (restored afterwards): a
    minimal cut of at most ``max_cut`` links, the turn (default moving side, as a sequence's
    ``turnQuarters`` does), then with or without every latch that closes after it; with
    ``early_latches`` also each of these after every latch that can close first (off by default:
    the previous turn's latches mostly make the same ones, and it doubles the branching)."""
    snap = s.snapshot()
    out: list[list[Op]] = []
    early = latches(s) if early_latches else []
    for before in ([], early) if early else ([],):
        s.restore(snap)
        for op in before:
            op.apply(s)
        base = s.snapshot()
        for ops in _minimal_cuts(s, base, _openable(s, reversible), m, q, max_cut):
            s.rotate(m, q)
            steps = [*before, *ops, Op("rotate", m, q)]
            out.append(steps)
            after = latches(s)
            if after:
                out.append(steps + after)
    s.restore(snap)
    return out


def guided(start: Structure, target: Structure | Goal, actors: Iterable[int], *,
           signs: Iterable[int] = (1, -1), skeleton_signs: Iterable[int] = (), max_cut: int = 3,
           max_states: int = 20000, reversible: bool = True, early_latches: bool = False) -> Plan:
    """A sequence whose quarter turns are made by ``actors`` in that order (a known solution's
    skeleton, e.g. USSR's eight-to-car), the search choosing for each turn its sign (the known
    solution's sign convention may differ), the latches before it, the links it must open and
    the latches after it (``_turn_steps``). Depth first over the turns, one visit per state and
    turn; a state whose cells are the target's after the last turn is finished by its latches.
    Bounded by ``max_states`` visits; ``Plan.reason`` says how close it came otherwise."""
    try:
        goal = target if isinstance(target, Goal) else Goal(target)
    except (AttributeError, TypeError, ValueError, KeyError) as error:
        return Plan(False, reason=f"not a target structure: {error}")
    if not isinstance(start, Structure):
        return Plan(False, reason="not a start structure")
    order = list(actors)
    order_signs = list(skeleton_signs)
    if order_signs and len(order_signs) != len(order):
        return Plan(False, reason="give one skeleton sign per actor, or none")
    if goal.size != len(start.modules) or any(m not in start.modules for m in order):
        return Plan(False, reason="the target's modules or the actors are not the start's")
    s = start.copy()
    if not goal.places:
        goal.aim(s)
    seen: set = set()
    visits = 0
    best: tuple[float, int] = (float("inf"), 0)

    def search(i: int, ops: tuple[Op, ...]) -> list[Op] | None:
        nonlocal visits, best
        key = (_key(s), i)
        if key in seen or visits >= max_states:
            return None
        seen.add(key)
        visits += 1
        snap = s.snapshot()
        if i == len(order):
            done = _finish(s, goal)
            if done is not None:
                return [*ops, *done]
            best = min(best, (goal.estimate(s), -i))
            return None
        best = min(best, (goal.estimate(s), -i))
        children = []  # the skeleton's sign first, then the closest to the target, the shortest
        first = order_signs[i] if order_signs else 0
        for q in sorted(signs, key=lambda q: q != first):
            for steps in _turn_steps(s, order[i], q, max_cut, reversible, early_latches):
                s.restore(snap)
                for op in steps:
                    op.apply(s)
                children.append((q != first, goal.estimate(s), len(steps), len(children), steps))
        for *_, steps in sorted(children, key=lambda c: c[:4]):
            s.restore(snap)
            for op in steps:
                op.apply(s)
            found = search(i + 1, (*ops, *steps))
            if found is not None:
                return found
        s.restore(snap)
        return None

    found = search(0, ())
    if found is not None:
        return Plan(True, found, expanded=visits, final=s.copy())
    return Plan(False, reason=f"no sequence with these turns within {visits} states (closest: "
                f"{best[0]:g} lattice steps away after turn {-best[1]})", expanded=visits)


def prune(start: Structure, ops: list[Op], target: Structure | Goal) -> list[Op]:
    """``ops`` without the latches that a later step opens again when leaving both out still
    replays and reaches ``target`` (a search that latches every link it can makes some)."""
    goal = target if isinstance(target, Goal) else Goal(target)
    out = list(ops)
    i = 0
    while i < len(out):
        op = out[i]
        if op.kind == "latch":
            s = replay(start, out[:i])
            op.apply(s)
            link = next((k for k in s.links() if (k.a, k.a_physical) == (op.module, op.arg)
                         or (k.b, k.b_physical) == (op.module, op.arg)), None)
            later = None if link is None else next(
                (j for j in range(i + 1, len(out)) if out[j].kind == "unlatch" and
                 (out[j].module, out[j].arg) in ((link.a, link.a_physical), (link.b, link.b_physical))),
                None)
            if later is not None:
                shorter = out[:i] + out[i + 1:later] + out[later + 1:]
                try:
                    if goal.reached(replay(start, shorter)):
                        out = shorter
                        continue
                except ValueError:
                    pass
        i += 1
    return out
