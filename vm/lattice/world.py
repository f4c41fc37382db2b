"""The physics-free lattice world: one ``vm.runtime.ModuleRuntime`` per module of a ``Structure``,
talking only through ``LatticeHal`` (docs/architecture.md rule 4).

Time advances in ticks of ``tick_s``. Each tick: joints move, due packets are delivered, then the
runtimes step in module-id order. Fast path: a module is stepped only when it has something to do
(a packet just arrived, packets waiting for acknowledgement, tasks queued, event handlers
installed); when no module has anything to do and nothing is in flight, time jumps to the end of
the run. Every random choice (loss, corruption, jitter, the runtimes' own) derives from ``seed``.

Structures that change (docs/simulator.md): connector actions latch or unlatch at once; a
TURN_QUARTERS motion is checked when it starts, takes the joint's time, and moves the carried
modules' cells and orientations exactly when it ends (checked again then: a motion started
meanwhile may block it). The older joint commands never move the structure: a joint that holds
modules on both hemispheres and moves by them is reported once ("joint_unmodelled"). Outside
changes (``vm.lattice.outside``) happen at their times. Every change is an event in ``events``
and goes to ``on_change`` (time, module, kind, detail) if set.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Any

from vm.isa.targets import DEFAULT, Target
from vm.lattice.changes import Change
from vm.lattice.hal import LatticeHal
from vm.lattice.joint import wrap
from vm.lattice.network import Counters, Network
from vm.lattice.outside import OutsideChange
from vm.lattice.structure import ModuleSpec, Structure
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_firmware import make_runtime

Vec = tuple[int, int, int]
Event = tuple[float, int, str, dict[str, Any]]


@dataclass(frozen=True)
class ModuleState:
    """What a module has learned and done, next to the truth from the structure."""

    id: int
    role: int
    role_name: str
    position: Vec | None
    axis: int | None
    mapping: tuple[int, ...] | None
    true_position: Vec
    true_axis: int
    true_mapping: tuple[int, ...]
    errors: list[tuple[float, str]]
    role_history: list[tuple[float, int]]
    programs_run: int

    @property
    def frame_correct(self) -> bool:
        return (self.position, self.axis, self.mapping) == (
            self.true_position, self.true_axis, self.true_mapping)


class LatticeWorld:
    def __init__(self, structure: Structure, role_table: RoleTable, *, seed: int = 0,
                 packet_loss: float = 0.0, packet_corruption: float = 0.0, latency_s: float = 0.01,
                 latency_jitter_s: float = 0.0, obstacles: frozenset[Vec] = frozenset(),
                 joint_speed_turns_per_s: float = 1 / 6, tick_s: float = 0.01,
                 sensor_range_steps: int = 2, modules_visible: bool = False,
                 target: Target = DEFAULT, changes: list[OutsideChange] | None = None) -> None:
        if tick_s <= 0 or joint_speed_turns_per_s <= 0 or sensor_range_steps < 1:
            raise ValueError("tick, joint speed and sensor range must be positive")
        self.structure = structure
        structure.listeners.append(self._structure_changed)
        self.role_table = role_table
        self._joint_speed = joint_speed_turns_per_s * 360.0
        self._turning: dict[int, tuple[int, int | None, float]] = {}  # quarters, moving, turns at start
        self._unmodelled: set[int] = set()
        self.outside = sorted(changes or [], key=lambda c: c.t)
        self.detached: dict[int, float] = {}  # module -> time it was taken away
        self.on_change: Any = None  # (t, module, kind, detail) of every change, or None
        self.make_recorder: Any = None  # module id -> its runtime's on_event (for attached modules)
        self.seed = seed
        self.tick_s = tick_s
        self.target = target  # the VM profile every module runs (vm.isa.targets)
        self.ticks = 0
        self._order = sorted(structure.modules)
        self._woken: set[int] = set()
        self._modules_visible = modules_visible
        self.obstacles: frozenset[Vec] = frozenset()
        self.set_obstacles(obstacles)
        self.sensor_range_steps = sensor_range_steps
        self.network = Network(structure, random.Random(seed), loss=packet_loss,
                               corruption=packet_corruption, latency_s=latency_s, jitter_s=latency_jitter_s)
        self.events: list[Event] = []
        self.hals: dict[int, LatticeHal] = {}
        self.runtimes: dict[int, ModuleRuntime] = {}
        for mid in structure.modules:
            self._add_runtime(mid)

    def _add_runtime(self, mid: int) -> None:
        hal = LatticeHal(self, mid, self._joint_speed)
        runtime = make_runtime(hal, self.role_table, module_id=mid, seed=self.seed, target=self.target)
        runtime.on_event = self.make_recorder(mid) if self.make_recorder else self._recorder(mid)
        self.hals[mid], self.runtimes[mid] = hal, runtime

    # ---- the hal's view of the world -------------------------------------------------------
    def now(self) -> float:
        return self.ticks * self.tick_s

    def transmit(self, source: int, physical: int, packet: bytes) -> None:
        self.network.send(self.now(), source, physical, packet)

    # ---- driving ---------------------------------------------------------------------------
    def inject(self, fragment: bytes, module_id: int | None = None) -> None:
        """Enter a fragment at the entry module. Injecting elsewhere is for tests: a module that
        has no frame yet takes the origin's."""
        mid = self.structure.entry if module_id is None else module_id
        self.runtimes[mid].inject(bytes(fragment))
        self._woken.add(mid)

    def set_obstacles(self, cells: frozenset[Vec]) -> None:
        """Lattice cells that proximity sensors see (plus the modules, if ``modules_visible``)."""
        cells = frozenset(tuple(c) for c in cells)  # type: ignore[misc]
        self._obstacle_cells = cells
        self.structure.blocked = cells  # no carried module moves through an obstacle
        if self._modules_visible:
            cells |= {m.position for m in self.structure.modules.values()}
        self.obstacles = cells
        self._woken.update(self._order)

    def advance(self, dt: float) -> None:
        """Run for ``dt`` seconds (rounded to whole ticks)."""
        end = self.ticks + max(0, round(dt / self.tick_s))
        while self.ticks < end:
            if self.outside and self.outside[0].t <= self.now() + 1e-9:
                self._apply_outside(self.outside.pop(0))
                continue
            if not self._woken and self.network.in_flight() == 0 and not self._busy() \
                    and not self._turning:
                self._jump(min(end, self._next_outside_tick()))
                continue
            self._tick()

    run = advance

    def run_until_quiet(self, max_s: float) -> bool:
        """Run until nothing is in flight and no module has work left; False if ``max_s`` ran out."""
        end = self.ticks + round(max_s / self.tick_s)
        while self.ticks < end:
            if not self._woken and self.network.in_flight() == 0 and not self._busy(events=False):
                return True
            self._tick()
        return False

    # ---- observing -------------------------------------------------------------------------
    @property
    def counters(self) -> Counters:
        return self.network.counters

    def state(self, module_id: int) -> ModuleState:
        r, spec = self.runtimes[module_id], self.structure.modules[module_id]
        return ModuleState(module_id, r.role, self.role_table.name(r.role), r.position, r.axis, r.mapping,
                           spec.position, spec.axis, self.structure.physical_map(module_id),
                           list(r.errors), list(r.role_history), r.programs_run)

    def states(self) -> list[ModuleState]:
        return [self.state(mid) for mid in self._order]

    def roles_by_name(self) -> dict[int, str | None]:
        names = self.role_table.name
        return {mid: (None if r.role == 0 else names(r.role)) for mid, r in self.runtimes.items()}

    def report(self) -> dict[str, Any]:
        """A JSON-able summary: time, link counters, and per module what it learned and did."""
        modules = [{"id": st.id, "role": st.role_name if st.role else None, "position": st.position,
                    "axis": st.axis, "frame_correct": st.frame_correct, "programs_run": st.programs_run,
                    "errors": [m for _, m in st.errors]} for st in self.states()]
        return {"time_s": round(self.now(), 6), "links": self.counters.as_dict(), "modules": modules,
                "events": len(self.events)}

    # ---- internals -------------------------------------------------------------------------
    def _next_outside_tick(self) -> int:
        if not self.outside:
            return 1 << 62
        return max(self.ticks + 1, round(self.outside[0].t / self.tick_s))

    def _tick(self) -> None:
        self.ticks += 1
        for hal in self.hals.values():
            hal.joint.advance(self.tick_s)
        if self._turning:
            self._end_turns()
        for packet in self.network.due(self.now()):
            self.runtimes[packet.target].receive(packet.physical, packet.packet)
            self._woken.add(packet.target)
        woken, self._woken = self._woken, set()
        for mid in self._order:
            if mid in woken or self.runtimes[mid].needs_step():
                self.runtimes[mid].step()


    def _jump(self, end: int) -> None:
        dt = (end - self.ticks) * self.tick_s
        for hal in self.hals.values():
            hal.joint.advance(dt)
        self.ticks = end

    # ---- structures that change ------------------------------------------------------------
    def act(self, mid: int, kind: str, arg: int) -> int | None:
        """A module's connector or joint action (its hal): 1 or 0 at once, or None while a turn runs."""
        s = self.structure
        if mid in self._turning or mid not in s.modules:
            reason = "the module is turning" if mid in s.modules else "the module was taken away"
            self.note(mid, f"{'rotation' if kind == 'turn' else kind}_failed", {"reason": reason})
            return 0
        if kind == "connect":
            return self._answer(s.latch(mid, arg), "connect")
        if kind == "disconnect":
            return self._answer(s.unlatch(mid, arg), "disconnect")
        check = s.rotate(mid, arg, apply=False)
        if not check.ok:
            return self._answer(check, "rotation")
        if arg == 0:
            return 1
        joint = self.hals[mid].joint
        self._turning[mid] = (arg, check.moving, joint.turns)
        self.hals[mid].watch = True
        joint.rotate_by(90.0 * arg)
        self.note(mid, "rotation_start", {"quarters": arg, "moving": _HEMISPHERES[check.moving or 0],
                                          "carried": list(check.moved)})
        return None

    def turning(self) -> dict[int, tuple[int, int | None, float]]:
        """Quarter turns under way (for viewers): module -> (quarters, moving hemisphere as given to
        ``structure.rotate``, degrees turned so far, signed like quarters)."""
        return {mid: (q, moving, (self.hals[mid].joint.turns - start) * (360.0 if q > 0 else -360.0))
                for mid, (q, moving, start) in self._turning.items()}

    def _answer(self, change: Change, kind: str) -> int:
        if not change.ok:
            self.note(change.module, f"{kind}_failed", {**_where(change), "cause": change.cause,
                                                         "reason": change.reason})
        return int(change.ok)

    def _end_turns(self) -> None:
        for mid, (quarters, moving, start) in list(self._turning.items()):
            hal = self.hals[mid]
            if hal.joint.is_turning():
                continue
            del self._turning[mid]
            hal.refresh()
            done = abs(hal.joint.turns - start) * 4
            change = None
            if abs(done - abs(quarters)) < 1e-6:
                change = self.structure.rotate(mid, quarters, moving=moving)
            if change is not None and change.ok:
                hal.result = 1
                continue
            # the structure did not move: the joint ends where it started (it stalled)
            hal.joint.angle = wrap(hal.joint.angle - (90.0 if quarters > 0 else -90.0) * done)
            reason = change.reason if change is not None else "the joint was stopped or given another command"
            self.note(mid, "rotation_failed", {"quarters": quarters, "cause": change.cause if change else
                                               "interrupted", "reason": reason})
            hal.result = 0

    def watches(self, mid: int, both_sides: bool) -> bool:
        """Whether ``mid``'s hal must tell ``legacy_motion`` of its older joint commands."""
        return mid in self._turning or (both_sides and mid not in self._unmodelled)

    def legacy_motion(self, mid: int) -> None:
        """After an older joint command: it ends a quarter turn under way (which fails: the
        structure did not move); a joint holding modules on both hemispheres that it sets turning
        moves only its angle (the lattice cannot hold angles between quarters), reported once."""
        hal = self.hals[mid]
        if mid in self._turning:
            quarters = self._turning.pop(mid)[0]
            hal.result = 0
            hal.refresh()
            self.note(mid, "rotation_failed", {"quarters": quarters, "cause": "interrupted",
                                               "reason": "a joint command ended the quarter turn"})
        if mid in self._unmodelled or mid not in self.structure.modules or not hal.joint.is_turning():
            return
        connected = hal.connected_channels()
        if any(c < 4 for c in connected) and any(c >= 4 for c in connected):
            self._unmodelled.add(mid)
            hal.watch = False
            self.note(mid, "joint_unmodelled", {"reason": "the joint holds modules on both hemispheres; "
                                                "the lattice world turns only its angle (use turnQuarters "
                                                "to move them)"})

    def _structure_changed(self, change: Change) -> None:
        kinds = {"latch": "connect", "unlatch": "disconnect", "rotate": "rotation_end",
                 "add": "attach", "remove": "detach"}
        detail: dict[str, Any] = _where(change)
        if change.op == "rotate":
            detail["quarters"] = change.quarters
            detail["carried"] = list(change.moved)
        if change.op != "remove":
            self.note(change.module, kinds[change.op], detail)
        self.network.refresh()
        for hal in self.hals.values():
            hal.refresh()
        if self._modules_visible:
            self.set_obstacles(self._obstacle_cells)
        self._woken.update(self._order)
        if change.parts:
            self.note(change.module, "split", {"parts": [sorted(p) for p in change.parts]})

    def _apply_outside(self, c: OutsideChange) -> None:
        s = self.structure
        detail = {"change": c.text or c.describe()}
        if c.kind == "stop":
            runtime = self.runtimes.get(c.module)
            if runtime is None or c.module in self.detached:
                self.note(c.module, "outside_failed", {**detail, "reason": f"no module {c.module}"})
                return
            runtime.halted = True
            self.hals[c.module].joint.stop()
            self.note(c.module, "outside", detail)
            return
        if c.kind in ("jam", "fail"):  # the latch no longer moves, or once (changes.py)
            if c.module not in s.modules or c.connector is None:
                self.note(c.module, "outside_failed", {**detail, "reason": f"no module {c.module}"})
                return
            if c.kind == "jam":
                s.jammed = s.jammed | {(c.module, c.connector)}
            else:
                s.failing = s.failing | {(c.module, c.connector)}
            self.note(c.module, "outside", detail)
            return
        if c.kind == "detach":
            self.note(c.module, "outside", detail)
            change = s.remove(c.module)
            if change.ok:
                self.detached[c.module] = self.now()
                self._order = [m for m in self._order if m != c.module]
                self.runtimes[c.module].halted = True
                self.hals[c.module].joint.stop()
            else:
                self.note(c.module, "outside_failed", {**detail, "reason": change.reason})
            return
        self.note(c.module, "outside", detail)
        change = s.add(ModuleSpec(c.module, c.cell, c.axis, c.mount))  # type: ignore[arg-type]
        if not change.ok:
            self.note(c.module, "outside_failed", {**detail, "reason": change.reason})
            return
        self._add_runtime(c.module)
        self._order = sorted(self._order + [c.module])
        self._woken.add(c.module)

    def note(self, mid: int, kind: str, detail: dict[str, Any]) -> None:
        self.events.append((self.now(), mid, kind, detail))
        if self.on_change is not None:
            self.on_change(self.now(), mid, kind, detail)

    def _busy(self, events: bool = True) -> bool:
        return any(r.needs_step(events) for r in self.runtimes.values())

    def _recorder(self, mid: int):  # noqa: ANN202 - a closure over the module id
        def record(kind: str, detail: dict[str, Any]) -> None:
            self.events.append((self.now(), mid, kind, detail))
        return record


_HEMISPHERES = ("north", "south")


def _where(change: Change) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if change.connector is not None:
        out["connector"] = change.connector
    if change.link is not None:
        link = change.link
        out["link"] = [link.a, link.a_physical, link.b, link.b_physical]
    return out
