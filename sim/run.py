"""Run a compiled program on a structure, in the physics world or the lattice world.

``simulate`` builds a ``Run`` (the one run loop), which injects the program at the entry module
following the compiler's injection plan and runs for the requested simulated time; it returns the
report (``sim.report``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from rdcd_core.compiler.program import CompiledProgram
from sim import params
from sim.obstacles import Box, parse_obstacle
from sim.report import build_report, source_of
from vm.isa.targets import TARGETS
from vm.lattice.structure import Structure
from vm.packets import PACKET_BUDGET, TYPE_NAMES
from vm.roles import RoleTable

Progress = Callable[[float, float], None]  # (simulated seconds done, total)
CHUNK_S = 0.5
MAX_OBSTACLE_CELLS = 200_000  # larger boxes are not enumerated into lattice cells


@dataclass
class Options:
    world: str = "physics"
    config: str = "car7"
    obstacle: str = "none"
    duration: float = 60.0
    seed: int = 0
    packet_loss: float = 0.0
    gui: bool = False
    record: str | None = None
    progress: Progress | None = None
    realtime: bool = False  # pace the GUI at wall-clock speed
    vm: str = "default"  # the VM profile every module runs: a name in vm.isa.targets.TARGETS
    recording: Any = None  # a sim.replay.recording.Recording to fill, or None
    # outside changes (vm.lattice.outside.OutsideChange), validated before the run
    outside_changes: list[Any] = field(default_factory=list)
    # module -> (coordinates, axis, virtual-to-physical map) it holds when the run starts, as
    # learned in an earlier run (a sequence run backwards, docs/reconfiguration.md); the others
    # learn theirs from the program's packets
    frames: dict[int, tuple[Any, int, tuple[int, ...]]] = field(default_factory=dict)


def role_table(program: CompiledProgram) -> RoleTable:
    """The VM's role table for ``program`` (role id -> name, instance-of), given to every module.
    It lives here, where the compiler's and the VM's layers meet (rdcd_core imports only vm.isa)."""
    return RoleTable({r.id: r.name for r in program.roles},
                     {r.id: frozenset(r.instance_of) for r in program.roles})


def simulate(program: CompiledProgram, structure: Structure, options: Options) -> dict[str, Any]:
    start = time.perf_counter()
    run = Run(program, structure, options)
    try:
        run.run_to_end()
        result = run.finish()
    finally:
        run.close()
    wall = time.perf_counter() - start
    return build_report(program, run.structure, run.roles, options, result, wall, start=structure)


@dataclass
class RunResult:
    runtimes: dict
    events: list[dict[str, Any]]
    counters: dict[str, int]
    tracking: Any = None  # sim.world.Tracking in the physics world
    boxes: list[Box] = field(default_factory=list)
    start_positions: dict[int, tuple[float, float]] = field(default_factory=dict)


def _recorder(events: list[dict[str, Any]], clock: Callable[[], float], mid: int,
              program: CompiledProgram | None = None, sources: dict[int, dict] | None = None) -> Callable:
    last_command: list[dict[str, Any]] = [{}]

    def record(kind: str, detail: dict[str, Any]) -> None:
        if kind == "command":  # behaviours repeat the same command every tick: keep the changes
            if detail == last_command[0]:
                return
            last_command[0] = dict(detail)
        if kind == "action" and program is not None:  # where in the program: fragment, pc, line
            detail = {k: v for k, v in detail.items() if k not in ("code", "pc")} | \
                source_of(program, detail.get("code", b""), detail.get("pc"))
            if sources is not None:
                sources[mid] = {k: detail[k] for k in ("fragment", "pc", "line") if k in detail}
        events.append({"t": round(clock(), 3), "module": mid, "kind": kind, "detail": dict(detail)})
    return record


# the structure's events that a module's own action caused: they name the action's source line
_ACTION_RESULTS = frozenset({"connect", "disconnect", "connect_failed", "disconnect_failed", "rotation_start",
                             "rotation_end", "rotation_failed"})


def _change_recorder(events: list[dict[str, Any]], sources: dict[int, dict]) -> Callable:
    def record(t: float, mid: int, kind: str, detail: dict[str, Any]) -> None:
        detail = dict(detail)
        if kind in _ACTION_RESULTS and mid in sources:
            detail.update(sources[mid])
        events.append({"t": round(t, 3), "module": mid, "kind": kind, "detail": detail})
    return record


def inject_program(program: CompiledProgram, inject: Callable[[bytes], None]) -> None:
    """Enter the program's fragments in the order of the compiler's injection plan."""
    for name in program.injection:
        inject(program.fragment(name).code)


def _hold_frames(runtimes: dict, frames: dict[int, tuple[Any, int, tuple[int, ...]]]) -> None:
    """Every module named in ``frames`` starts with that frame (before the program enters)."""
    for mid, (position, axis, mapping) in sorted(frames.items()):
        if mid in runtimes:
            runtimes[mid].hold_frame(position, axis, mapping)


def _lattice_cells(boxes: list[Box], structure: Structure) -> frozenset[tuple[int, int, int]]:
    """Lattice places whose centre lies inside an obstacle, at the structure's heights."""
    u = params.LATTICE_UNIT
    zs = {s.position[2] for s in structure.modules.values()}
    cells = set()
    for box in boxes:
        x0, x1 = round((box.x - box.w / 2) / u), round((box.x + box.w / 2) / u)
        y0, y1 = round((box.y - box.l / 2) / u), round((box.y + box.l / 2) / u)
        if (x1 - x0 + 1) * (y1 - y0 + 1) * len(zs) > MAX_OBSTACLE_CELLS:
            continue  # too large to enumerate; nothing in a static lattice reaches it anyway
        cells.update((x, y, z) for x in range(x0, x1 + 1) for y in range(y0, y1 + 1) for z in zs)
    return frozenset(cells)


def _oversize_recorder(events: list[dict[str, Any]]) -> Callable:
    """An event for each packet a module could not send because it is over the IR packet limit
    (once per module and packet: the VM's retries of it are counted by the network only)."""
    seen: set[tuple[int, bytes]] = set()

    def record(now: float, source: int, physical: int, packet: bytes) -> None:
        key = (source, packet[:1] + packet[7:])  # the header's id and coordinates vary per send
        if key in seen:
            return
        seen.add(key)
        events.append({"t": round(now, 3), "module": source, "kind": "packet_not_sent",
                       "detail": {"type": TYPE_NAMES.get(packet[0], str(packet[0])), "bytes": len(packet),
                                  "limit": PACKET_BUDGET, "connector": physical}})
    return record


class Run:
    """One simulation, advanced piece by piece: the one run loop of ``simulate``, sweeps, replays
    and the debugger (``debug``). Building it makes the world, attaches the recorders and injects
    the program; ``advance_chunk`` runs the next piece of at most ``CHUNK_S`` simulated seconds
    (the pieces are the same whoever drives the run, so every driver sees the same world);
    ``finish`` gives the ``RunResult``; ``close`` frees the world (always call it).

    A driver that must stop inside a piece (a debugger at an instruction) does so from a
    ``vm.observer.RuntimeObserver`` attached to the runtimes: the piece waits for it."""

    def __init__(self, program: CompiledProgram, structure: Structure, options: Options) -> None:
        if options.vm not in TARGETS:
            raise ValueError(f"unknown VM profile {options.vm!r}; known: {', '.join(TARGETS)}")
        # the run changes its own copy: the caller's structure (a sweep's, a debugger's) stays
        self.start_structure = structure
        structure = structure.copy()
        self.program, self.structure, self.options = program, structure, options
        self.boxes = parse_obstacle(options.obstacle)
        self.roles = role_table(program)
        self.events: list[dict[str, Any]] = []
        self._sources: dict[int, dict] = {}  # per module, where its last action is in the program
        self.done = 0.0  # simulated seconds advanced
        self.world: Any = None
        self.starts: dict[int, tuple[float, float]] = {}
        self._recorder: Any = None
        if options.world == "lattice":
            self._build_lattice()
        else:
            self._build_physics()

    @property
    def finished(self) -> bool:
        return self.done >= self.options.duration - 1e-9

    @property
    def time(self) -> float:
        """The world's simulated time."""
        return self.world.now() if self.options.world == "lattice" else self.world.time

    @property
    def runtimes(self) -> dict:
        return self.world.runtimes

    def advance_chunk(self) -> bool:
        """Run the next piece; False (and nothing done) once the duration is reached."""
        options = self.options
        if self.finished:
            return False
        step = min(CHUNK_S, options.duration - self.done)
        tick = time.perf_counter()
        self._advance(step)
        self.done += step
        if self._recorder is not None:
            self._recorder.capture()
        if options.progress:
            options.progress(self.done, options.duration)
        if options.realtime:
            time.sleep(max(0.0, step - (time.perf_counter() - tick)))
        return True

    def run_to_end(self) -> None:
        while self.advance_chunk():
            pass

    def finish(self) -> RunResult:
        """The result of the run so far (the GIF, if asked for, is written now)."""
        if self.options.world == "lattice":
            world = self.world
            return RunResult(world.runtimes, self.events, world.counters.as_dict(), None, self.boxes)
        if self._recorder is not None:
            self._recorder.save(self.options.record)
        world = self.world
        return RunResult(world.runtimes, self.events, world.network.counters.as_dict(), world.tracking,
                         self.boxes, self.starts)

    def close(self) -> None:
        if self.options.world != "lattice" and self.world is not None:
            self.world.close()

    def hook_events(self) -> None:
        """Record the story of the run (for the report) from this run's world into ``events``;
        again after a copy of the run (``copy.deepcopy`` keeps the hooks of the original)."""
        world, events = self.world, self.events
        world.network.on_oversize = _oversize_recorder(events)
        lattice = self.options.world == "lattice"
        clock = world.now if lattice else (lambda: world.time)
        sources = self._sources  # the run's: a copy of the run keeps what its modules asked

        def recorder(mid: int) -> Callable:
            return _recorder(events, clock, mid, self.program, sources)
        for mid, runtime in world.runtimes.items():
            runtime.on_event = recorder(mid)
        world.make_recorder = recorder  # for modules attached from outside
        world.on_change = _change_recorder(events, sources)  # the structure's changes
        if lattice:
            return
        world.on_detection = lambda mid, k: events.append(
            {"t": round(world.time, 3), "module": mid, "kind": "sensor", "detail": {"sensor": k}})

    # ---- building --------------------------------------------------------------------------
    def _build_physics(self) -> None:
        from sim.world import PhysicsWorld

        options, structure = self.options, self.structure
        world = PhysicsWorld(structure, obstacles=self.boxes, seed=options.seed,
                             packet_loss=options.packet_loss, gui=options.gui, visuals=bool(options.record),
                             changes=options.outside_changes)
        self.world = world
        try:
            runtimes = world.add_runtimes(self.roles, options.seed, TARGETS[options.vm])
            self.hook_events()
            self._advance = world.advance
            if options.recording is not None:
                options.recording.attach_physics(world, runtimes)
                self._advance = options.recording.sampled(world.advance, lambda: world.time)
            _hold_frames(runtimes, options.frames)
            inject_program(self.program, runtimes[structure.entry].inject)
            self.starts = {mid: (float(c[0]), float(c[1])) for mid, c in world.module_centres().items()}
            if options.record:
                from sim.record import GifRecorder
                self._recorder = GifRecorder(world, self.roles)
        except BaseException:
            world.close()
            raise

    def _build_lattice(self) -> None:
        from vm.lattice.world import LatticeWorld

        options, structure = self.options, self.structure
        world = LatticeWorld(structure, self.roles, seed=options.seed, packet_loss=options.packet_loss,
                             latency_s=params.IR_LATENCY_S,
                             joint_speed_turns_per_s=1 / params.JOINT_TURN_PERIOD_S,
                             obstacles=_lattice_cells(self.boxes, structure), target=TARGETS[options.vm],
                             changes=options.outside_changes)
        self.world = world
        self.hook_events()
        self._advance = world.advance
        if options.recording is not None:
            options.recording.attach_lattice(world)
            self._advance = options.recording.sampled(world.advance, world.now)
        _hold_frames(world.runtimes, options.frames)
        inject_program(self.program, world.inject)
