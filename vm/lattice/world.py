"""The physics-free lattice world: one ``vm.runtime.ModuleRuntime`` per module of a ``Structure``,
talking only through ``LatticeHal`` (docs/architecture.md rule 4).

Time advances in ticks of ``tick_s``. Each tick: joints move, due packets are delivered, then the
runtimes step in module-id order. Fast path: a module is stepped only when it has something to do
(a packet just arrived, packets waiting for acknowledgement, tasks queued, event handlers
installed); when no module has anything to do and nothing is in flight, time jumps to the end of
the run. Every random choice (loss, corruption, jitter, the runtimes' own) derives from ``seed``.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Any

from vm.isa.targets import DEFAULT, Target
from vm.lattice.hal import LatticeHal
from vm.lattice.network import Counters, Network
from vm.lattice.structure import Structure
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
                 target: Target = DEFAULT) -> None:
        if tick_s <= 0 or joint_speed_turns_per_s <= 0 or sensor_range_steps < 1:
            raise ValueError("tick, joint speed and sensor range must be positive")
        self.structure = structure
        self.role_table = role_table
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
            hal = LatticeHal(self, mid, joint_speed_turns_per_s * 360.0)
            runtime = make_runtime(hal, role_table, module_id=mid, seed=seed, target=target)
            runtime.on_event = self._recorder(mid)
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
        if self._modules_visible:
            cells |= {m.position for m in self.structure.modules.values()}
        self.obstacles = cells
        self._woken.update(self._order)

    def advance(self, dt: float) -> None:
        """Run for ``dt`` seconds (rounded to whole ticks)."""
        end = self.ticks + max(0, round(dt / self.tick_s))
        while self.ticks < end:
            if not self._woken and self.network.in_flight() == 0 and not self._busy():
                self._jump(end)
                return
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
                           spec.position, spec.axis, spec.mount.physical_map(), list(r.errors),
                           list(r.role_history), r.programs_run)

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
    def _tick(self) -> None:
        self.ticks += 1
        for hal in self.hals.values():
            hal.joint.advance(self.tick_s)
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

    def _busy(self, events: bool = True) -> bool:
        return any(r.needs_step(events) for r in self.runtimes.values())

    def _recorder(self, mid: int):  # noqa: ANN202 - a closure over the module id
        def record(kind: str, detail: dict[str, Any]) -> None:
            self.events.append((self.now(), mid, kind, detail))
        return record
