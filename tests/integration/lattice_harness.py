"""Runs of the compiled obstacle program (examples/obstacle_avoidance.rdcd, unmodified) in the
physics-free lattice world, shared by tests/integration and benchmarks/lattice_acceptance.py.

``start(config, seed=..., loss=...)`` compiles the program once per process (real front end, real
compiler), injects its fragments back to back at the entry module as ``rdcd simulate`` does, runs
until every module has accepted every fragment and all links are quiet, then a margin, and returns
a ``LatticeRun``: roles by module id, the fragments each module accepted (with repeats), run
counts, link figures and ``problems()``, the acceptance verdict (docs/simulator.md, docs/vm.md).
``reverse_scenario(run)`` then puts an obstacle cell ahead of a front wheel's watched sensor and
follows the Reverse mixin through the structure.

Fragments are identified on each module by the (packet id, size) of its "program" log entries:
the entry module gives injected fragments ids in injection order, and diffusion keeps the id.
"""

from __future__ import annotations

import functools
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from rdcd_core.compiler import CompiledProgram, compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm.isa.targets import DEFAULT, Target
from vm.lattice.structure import Structure
from vm.lattice.world import LatticeWorld

ROOT = Path(__file__).resolve().parents[2]
PROGRAM = ROOT / "examples" / "obstacle_avoidance.rdcd"
CARS = ("car7", "car11", "car8-cyclic", "car17-wide")
WATCHED_SENSOR = {"RightWheel": 5, "LeftWheel": 1}  # the program's event_handler constants
STEER_DEG = 30.0
POLL_S = 0.1


@functools.cache
def compiled(target: str = "default", path: Path = PROGRAM) -> CompiledProgram:
    """The program compiled for ``target`` (a name in vm.isa.targets.TARGETS)."""
    text = path.read_text(encoding="utf-8")
    checked = check_text(text)
    if checked.has_errors or checked.model is None:
        raise AssertionError(f"{path.name} does not check: {checked.diagnostics}")
    program = compile_model(checked.model, text=text, target=target)
    if program.has_errors or not program.injection:
        raise AssertionError(f"{path.name} does not compile: {program.diagnostics}")
    return program


@dataclass
class LatticeRun:
    config: str
    seed: int
    loss: float
    structure: Structure
    world: LatticeWorld
    injected: dict[tuple[int, int], str]  # (packet id, size) at the entry → fragment name
    settled: bool = False  # every fragment everywhere and the links quiet within the limit
    quiet_s: float | None = None  # simulated time at which that was first seen
    settle_s: float | None = None  # when the last fragment was accepted or the last role taken
    loader: int | None = None  # the entry module when it loads the fragments as the firmware does
    wall_s: float = 0.0

    # ---- observations ----------------------------------------------------------------------
    def roles(self) -> dict[int, str | None]:
        return self.world.roles_by_name()

    def fragments_received(self) -> dict[int, list[str]]:
        """Fragment names in the order each module accepted them; repeats would mean a second run."""
        return {mid: [self.injected.get((d.get("id"), d.get("size")), f"other{d.get('id')}")  # type: ignore[misc]
                      for _, kind, d in r.event_log if kind == "program"]
                for mid, r in self.world.runtimes.items()}

    def run_counts(self) -> dict[int, dict[str, int]]:
        return {mid: dict(Counter(names)) for mid, names in self.fragments_received().items()}

    def last_change_s(self) -> float:
        return max((t for r in self.world.runtimes.values() for t, kind, _ in r.event_log
                    if kind in ("program", "role")), default=0.0)

    def errors(self) -> dict[int, list[str]]:
        return {mid: [m for _, m in r.errors] for mid, r in self.world.runtimes.items() if r.errors}

    def figures(self) -> dict[str, float | int | None]:
        stats = [r.stats() for r in self.world.runtimes.values()]
        links = self.world.counters
        return {"settle_s": self.settle_s, "sent": links.sent, "delivered": links.delivered,
                "dropped": links.dropped,
                "retransmissions": sum(s["retransmissions"] for s in stats),
                "duplicates": sum(s["duplicates"] for s in stats),
                "given_up": sum(s["given_up"] for s in stats), "wall_s": self.wall_s}

    # ---- the verdict -----------------------------------------------------------------------
    def problems(self) -> list[str]:
        """Everything that keeps this run from passing; empty when it passes."""
        found = [] if self.settled else [f"{self.config}: fragments not everywhere / links not quiet"]
        expected, roles = self.structure.expected_roles, self.roles()
        found += [f"module {m}: role {roles[m]}, expected {want}"
                  for m, want in sorted(expected.items()) if roles.get(m) != want]
        names = set(self.injected.values())
        for mid, counts in sorted(self.run_counts().items()):
            if mid == self.loader:
                continue
            if missing := names - set(counts):
                found.append(f"module {mid}: never got {sorted(missing)}")
            if twice := sorted(n for n, c in counts.items() if c > 1):
                found.append(f"module {mid}: accepted {twice} more than once")
            runtime = self.world.runtimes[mid]
            if runtime.programs_run != len(counts):
                found.append(f"module {mid}: {runtime.programs_run} program runs for {len(counts)} programs")
        found += [f"module {s.id}: learned {s.position}/{s.axis}, is at {s.true_position}/{s.true_axis}"
                  for s in self.world.states() if not s.frame_correct]
        found += [f"module {m}: error {e}" for m, errs in self.errors().items() for e in errs]
        return found


def start(config: str, *, seed: int = 0, loss: float = 0.0, spacing_s: float | None = 0.0,
          limit_s: float = 60.0, margin_s: float = 3.0, target: str = "default",
          vm: Target = DEFAULT, path: Path = PROGRAM) -> LatticeRun:
    """Inject the program and run until it has settled. ``spacing_s``: time between injections
    (0 = back to back, as ``rdcd simulate`` does); None = wait until each fragment has reached
    every module and the links are quiet (the spacing the compiler's injection plan asks for).
    ``target``: what the program (``path``) is compiled for; ``vm``: the VM profile the modules run."""
    began = time.perf_counter()
    program, structure = compiled(target, path), load_config(config)
    world = LatticeWorld(structure, role_table(program), seed=seed, packet_loss=loss, target=vm)
    entry_log = world.runtimes[structure.entry].event_log
    injected: dict[tuple[int, int], str] = {}
    loader = vm.quirks.firmware_controller  # the firmware's dcd_action: ids 0, 1, ... 8 s apart
    for index, name in enumerate(program.injection):
        before = len(entry_log)
        world.inject(program.fragment(name).code)
        accepted = [d for _, kind, d in entry_log[before:] if kind == "program"]
        if loader:
            injected[(index, len(program.fragment(name).code))] = name
            continue
        if accepted:
            injected[(accepted[0]["id"], accepted[0]["size"])] = name  # type: ignore[index]
        else:
            injected[(-1, len(injected))] = name  # refused at the entry: reported as never received
        if spacing_s is None:
            _diffuse(world, set(injected), limit_s)
        else:
            world.advance(spacing_s)
    run = LatticeRun(config, seed, loss, structure, world, injected)
    if loader:  # the entry module sends the fragments on and runs none of them
        run.loader = structure.entry
        limit_s += 8.0 * len(injected)
    run.settled = _diffuse(world, set(injected), limit_s, run.loader)
    if run.settled:
        run.quiet_s, run.settle_s = world.now(), run.last_change_s()
    world.advance(margin_s)
    run.wall_s = time.perf_counter() - began
    return run


def _diffuse(world: LatticeWorld, wanted: set[tuple[int, int]], limit_s: float,
             loader: int | None = None) -> bool:
    """Run until every module (but a loading entry module) has accepted every ``wanted`` program
    and the links are quiet."""
    while world.now() < limit_s:
        if _quiet(world) and all(wanted <= _accepted(r.event_log) for m, r in world.runtimes.items()
                                 if m != loader):
            return True
        world.advance(POLL_S)
    return False


def _quiet(world: LatticeWorld) -> bool:
    return world.network.in_flight() == 0 and not any(r.link.outbox for r in world.runtimes.values())


def _accepted(log: list[tuple[float, str, dict[str, object]]]) -> set[tuple[object, object]]:
    return {(d.get("id"), d.get("size")) for _, kind, d in log if kind == "program"}


# ---- the dynamic scenario: an obstacle ahead of a front wheel -------------------------------
@dataclass
class ReverseResult:
    detector: int  # the front wheel the obstacle was put in front of
    cell: tuple[int, int, int]
    detect_s: float | None = None  # simulated time from the obstacle appearing to the handler
    handlers: list[int] = field(default_factory=list)  # module of each handler firing
    reverse_s: float | None = None  # how long some wheel was in Reverse
    steered: dict[int, float] = field(default_factory=dict)  # axle → angle while all reversed
    spin: dict[int, tuple[float, float, float]] = field(default_factory=dict)  # wheel → before/in/after
    histories: dict[int, list[str]] = field(default_factory=dict)  # wheel → role names taken
    final_roles: dict[int, str | None] = field(default_factory=dict)
    final_axles: dict[int, float] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    wall_s: float = 0.0


def front_wheel(structure: Structure) -> tuple[int, tuple[int, int, int]]:
    """The first front wheel and the cell in sensor range straight out of its watched sensor."""
    for mid, role in sorted(structure.expected_roles.items()):
        if role in WATCHED_SENSOR and structure.modules[mid].position[1] > 0:
            x, y, z = structure.modules[mid].position
            dx, dy, dz = structure.physical_direction(mid, WATCHED_SENSOR[role])
            return mid, (x + 2 * dx, y + 2 * dy, z + 2 * dz)
    raise AssertionError(f"{structure.name}: no front wheel")


def reverse_scenario(run: LatticeRun, *, limit_s: float = 45.0) -> ReverseResult:
    """Obstacle cell ahead of a front wheel's watched sensor until its handler fires, then follow
    the Reverse mixin: every wheel takes ``Reverse@<role>``, spins backwards, the axles steer
    (front +30°, rear −30°), and everything returns to its base role and straight axles."""
    began = time.perf_counter()
    world, structure = run.world, run.structure
    expected = structure.expected_roles
    wheels = {m: r for m, r in expected.items() if r in WATCHED_SENSOR}
    axles = [m for m, r in expected.items() if r == "Axle"]
    detector, cell = front_wheel(structure)
    result = ReverseResult(detector, cell)
    before = {m: _spin(world, m) for m in wheels}
    first_event = len(world.events)
    t0 = world.now()
    world.set_obstacles(frozenset({cell}))
    while world.now() - t0 < 3.0 and not _handlers(world, first_event):
        world.advance(0.01)
    world.set_obstacles(frozenset())
    if _handlers(world, first_event):
        result.detect_s = round(_handlers(world, first_event)[0][0] - t0, 3)
    during: dict[int, float] = {}
    reverse_start = reverse_end = None
    while world.now() - t0 < limit_s:
        roles = world.roles_by_name()
        reversing = [m for m in wheels if (roles[m] or "").startswith("Reverse")]
        if reversing and reverse_start is None:
            reverse_start = world.now()
        if reverse_start is not None and not reversing:
            reverse_end = world.now()
            break
        if len(reversing) == len(wheels) and world.now() - reverse_start > 2.0 and not during:
            during = {m: _spin(world, m) for m in wheels}
            result.steered = {m: round(world.hals[m].joint_angle_deg(), 1) for m in axles}
        world.advance(POLL_S)
    world.advance(2.0)
    result.handlers = [m for _, m in _handlers(world, first_event)]
    if reverse_start is not None and reverse_end is not None:
        result.reverse_s = round(reverse_end - reverse_start, 2)
    after = {m: _spin(world, m) for m in wheels}
    result.spin = {m: (before[m], during.get(m, 0.0), after[m]) for m in wheels}
    names = world.role_table.name
    result.histories = {m: [names(r) for _, r in world.runtimes[m].role_history] for m in wheels}
    result.final_roles = world.roles_by_name()
    result.final_axles = {m: round(world.hals[m].joint_angle_deg(), 1) for m in axles}
    result.problems = _reverse_problems(result, structure, wheels, axles) + run.problems()
    result.wall_s = time.perf_counter() - began
    return result


def _reverse_problems(res: ReverseResult, structure: Structure, wheels: dict[int, str],
                      axles: list[int]) -> list[str]:
    found = []
    if res.handlers != [res.detector]:
        found.append(f"handler fired on {res.handlers}, expected once on module {res.detector}")
    if res.reverse_s is None:
        found.append("the wheels never went into Reverse and back")
    for m, base in wheels.items():
        history = res.histories[m]
        if history[-2:] != [f"Reverse@{base}", base]:
            found.append(f"wheel {m}: role history {history}, expected … Reverse@{base}, {base}")
        first, mid, last = res.spin[m]
        if not (first and mid * first < 0 < last * first):
            found.append(f"wheel {m}: spin before/during/after {res.spin[m]}, expected +/-/+")
    for m in axles:
        want = STEER_DEG if structure.modules[m].position[1] > 0 else -STEER_DEG
        if abs(res.steered.get(m, 0.0) - want) > 0.5:
            found.append(f"axle {m}: at {res.steered.get(m)}° while reversing, expected {want}°")
        if abs(res.final_axles[m]) > 0.5:
            found.append(f"axle {m}: left at {res.final_axles[m]}°, expected 0°")
    if res.final_roles != structure.expected_roles:
        found.append(f"final roles {res.final_roles}, expected {structure.expected_roles}")
    return found


def _handlers(world: LatticeWorld, since: int) -> list[tuple[float, int]]:
    return [(t, m) for t, m, kind, _ in world.events[since:] if kind == "handler"]


def _spin(world: LatticeWorld, mid: int) -> float:
    """Signed joint motion of module ``mid`` over 0.1 s (degrees; + is clockwise)."""
    before = world.hals[mid].joint_angle_deg()
    world.advance(0.1)
    return round((world.hals[mid].joint_angle_deg() - before + 180) % 360 - 180, 2)
