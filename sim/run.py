"""Run a compiled program on a structure, in the physics world or the lattice world.

``simulate`` injects the program at the entry module following the compiler's injection plan,
runs for the requested simulated time and returns the report (``sim.report``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from rdcd_core.compiler.program import CompiledProgram
from sim import params
from sim.obstacles import Box, parse_obstacle
from sim.report import build_report
from vm.isa.targets import TARGETS
from vm.lattice.structure import Structure
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


def role_table(program: CompiledProgram) -> RoleTable:
    """The VM's role table for ``program`` (role id -> name, instance-of), given to every module.
    It lives here, where the compiler's and the VM's layers meet (rdcd_core imports only vm.isa)."""
    return RoleTable({r.id: r.name for r in program.roles},
                     {r.id: frozenset(r.instance_of) for r in program.roles})


def simulate(program: CompiledProgram, structure: Structure, options: Options) -> dict[str, Any]:
    if options.vm not in TARGETS:
        raise ValueError(f"unknown VM profile {options.vm!r}; known: {', '.join(TARGETS)}")
    boxes = parse_obstacle(options.obstacle)
    roles = role_table(program)
    start = time.perf_counter()
    if options.world == "lattice":
        run = _run_lattice(program, structure, roles, boxes, options)
    else:
        run = _run_physics(program, structure, roles, boxes, options)
    wall = time.perf_counter() - start
    return build_report(program, structure, roles, options, run, wall)


@dataclass
class RunResult:
    runtimes: dict
    events: list[dict[str, Any]]
    counters: dict[str, int]
    tracking: Any = None  # sim.world.Tracking in the physics world
    boxes: list[Box] = field(default_factory=list)
    start_positions: dict[int, tuple[float, float]] = field(default_factory=dict)


def _recorder(events: list[dict[str, Any]], clock: Callable[[], float], mid: int) -> Callable:
    last_command: list[dict[str, Any]] = [{}]

    def record(kind: str, detail: dict[str, Any]) -> None:
        if kind == "command":  # behaviours repeat the same command every tick: keep the changes
            if detail == last_command[0]:
                return
            last_command[0] = dict(detail)
        events.append({"t": round(clock(), 3), "module": mid, "kind": kind, "detail": dict(detail)})
    return record


def inject_program(program: CompiledProgram, inject: Callable[[bytes], None]) -> None:
    """Enter the program's fragments in the order of the compiler's injection plan."""
    for name in program.injection:
        inject(program.fragment(name).code)


def _chunks(options: Options, advance: Callable[[float], None],
            on_chunk: Callable[[], None] | None = None) -> None:
    done = 0.0
    while done < options.duration - 1e-9:
        step = min(CHUNK_S, options.duration - done)
        tick = time.perf_counter()
        advance(step)
        done += step
        if on_chunk:
            on_chunk()
        if options.progress:
            options.progress(done, options.duration)
        if options.realtime:
            time.sleep(max(0.0, step - (time.perf_counter() - tick)))


def _run_physics(program: CompiledProgram, structure: Structure, roles: RoleTable, boxes: list[Box],
                 options: Options) -> RunResult:
    from sim.world import PhysicsWorld

    world = PhysicsWorld(structure, obstacles=boxes, seed=options.seed, packet_loss=options.packet_loss,
                         gui=options.gui, visuals=bool(options.record))
    try:
        events: list[dict[str, Any]] = []
        runtimes = world.add_runtimes(roles, options.seed, TARGETS[options.vm])
        for mid, runtime in runtimes.items():
            runtime.on_event = _recorder(events, lambda: world.time, mid)
        world.on_detection = lambda mid, k: events.append(
            {"t": round(world.time, 3), "module": mid, "kind": "sensor", "detail": {"sensor": k}})
        inject_program(program, runtimes[structure.entry].inject)
        starts = {mid: (float(c[0]), float(c[1])) for mid, c in world.module_centres().items()}
        recorder = None
        if options.record:
            from sim.record import GifRecorder
            recorder = GifRecorder(world, roles)
        _chunks(options, world.advance, recorder.capture if recorder else None)
        if recorder:
            recorder.save(options.record)
        return RunResult(runtimes, events, world.network.counters.as_dict(), world.tracking, boxes, starts)
    finally:
        world.close()


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


def _run_lattice(program: CompiledProgram, structure: Structure, roles: RoleTable, boxes: list[Box],
                 options: Options) -> RunResult:
    from vm.lattice.world import LatticeWorld

    world = LatticeWorld(structure, roles, seed=options.seed, packet_loss=options.packet_loss,
                         latency_s=params.IR_LATENCY_S,
                         joint_speed_turns_per_s=1 / params.JOINT_TURN_PERIOD_S,
                         obstacles=_lattice_cells(boxes, structure), target=TARGETS[options.vm])
    events: list[dict[str, Any]] = []
    for mid, runtime in world.runtimes.items():
        runtime.on_event = _recorder(events, world.now, mid)
    inject_program(program, world.inject)
    _chunks(options, world.advance)
    return RunResult(world.runtimes, events, world.counters.as_dict(), None, boxes)
