"""The world under the debugger: a ``sim.run.Run`` advanced in a thread of its own, watched
through a ``vm.observer.RuntimeObserver`` and held still at a *moment* by making that thread wait.

Moments are counted: every instruction about to execute, every runtime error, every packet sent
on a link and every boundary between two pieces of the run is one, numbered from 1 (0 is the
start, before anything ran). The world is deterministic, so moment n of one run is moment n of
any run of the same launch: going back to moment n is building the run again and running it,
silently, until moment n (``Goal``); finding *which* moment to go back to is one more silent run
that notes the candidates (``Scan``). Nothing in the VM is changed or patched.

Threads: the adapter's thread asks (``resume``, ``step``, ``pause``, ``go_back``, ``terminate``);
the world's thread runs and calls ``Sink`` methods when it stops or ends. While the world waits,
the adapter's thread reads it freely (nothing else touches it).
"""

from __future__ import annotations

import copy
import threading
import time
from array import array
from bisect import bisect_left, bisect_right
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from debug.code import CodeIndex
from debug.expr import Expr, ExprError
from rdcd_core.compiler.program import CompiledProgram
from sim.params import JOINT_MAX_TORQUE
from sim.run import Options, Run
from vm.interpreter import Frame
from vm.lattice.structure import Structure
from vm.observer import RuntimeObserver

RUNTIME, PACKET, COLLISION = "runtime", "packet", "collision"
# checkpoints: measured in the world thread's CPU time, which other work on the machine does not
# stretch (wall time would make copies more frequent on a loaded machine)
CHECKPOINT_WALL_S = 0.2  # seconds of running between two checkpoints (at least)
COPY_SHARE = 25  # ... and at least this many times what the last checkpoint's copy took (<= 4 %)
EXCEPTION_FILTERS = {
    RUNTIME: "Runtime errors (unknown instruction, store or queue full, stack overflow...)",
    PACKET: "Lost packets",
    COLLISION: "Collisions with the obstacle (physics world)",
}


class Aborted(BaseException):  # noqa: N818 - not an error: the run was discarded
    """Raised in the world's thread to end a run that is thrown away (a step back, the end)."""


class _ScanDone(BaseException):  # noqa: N818
    pass


@dataclass
class Breakpoint:
    id: int
    condition: Expr | None = None
    hit_condition: tuple[str, int] | None = None
    log: str | None = None
    role: int | None = None  # function breakpoints: only on modules of this role
    hits: int = 0
    kind: str = "breakpoint"  # or "function breakpoint"


@dataclass
class Stop:
    reason: str  # entry, breakpoint, function breakpoint, step, pause, exception, goto
    count: int
    time: float
    module: int | None = None  # the module at this moment (None: between pieces, at the start)
    frame: Frame | None = None  # the frame about to execute an instruction
    code: bytes | None = None  # where an error happened
    pc: int | None = None
    hit_ids: list[int] = field(default_factory=list)
    text: str = ""


@dataclass
class Step:
    module: int
    kind: str  # next, stepIn, stepOut
    instruction: bool
    frame: Frame | None
    line: int


@dataclass
class Checkpoint:
    count: int  # the boundary moment it was taken at
    time: float
    collided: bool
    run: Run | None  # a copy, never run itself: restoring copies it again; None: start again
    state: int | None  # PyBullet's saved state (physics world)


@dataclass
class Goal:
    count: int
    reason: str


@dataclass
class Scan:
    until: int
    wanted: Callable[[str, Any, Frame | None], bool]  # (kind, runtime, frame) -> a candidate?
    last: int = 0


class Sink:
    """What the world tells the adapter (called from the world's thread)."""

    def stopped(self, stop: Stop) -> None: ...
    def output(self, text: str, category: str = "console", line: int = 0) -> None: ...
    def ended(self, run: Run) -> None: ...
    def failed(self, message: str) -> None: ...


class _Observer(RuntimeObserver):
    instructions = True

    def __init__(self, engine: Engine) -> None:
        self.engine = engine

    def before_instruction(self, runtime: Any, frame: Frame) -> None:
        self.engine.on_instruction(runtime, frame)

    def error(self, runtime: Any, message: str, code: bytes | None, pc: int | None) -> None:
        self.engine.on_error(runtime, message, code, pc)


class Engine:
    def __init__(self, program: CompiledProgram, structure: Structure, options: Options, code: CodeIndex,
                 sink: Sink, names: Callable[[Any, Frame | None, Run], dict[str, Any]]) -> None:
        self.program, self.structure, self.options = program, structure, options
        self.code, self.sink, self.names = code, sink, names
        self.run: Run | None = None
        self.stop: Stop | None = None
        self.count = 0
        self.filters: set[str] = set()
        self.ended = False
        self._cv = threading.Condition()
        self._command: tuple[str, Any] | None = None
        self._thread: threading.Thread | None = None
        self._locations: dict[tuple[int, int], list[Breakpoint]] = {}
        self._tables: dict[bytes, dict[int, list[Breakpoint]]] = {}
        self._goal: Goal | None = None
        self._scan: Scan | None = None
        self._step: Step | None = None
        self._pause = False
        self._collided = False
        self._special = False  # any of the above: the per-instruction fast path is left
        self._trail: defaultdict[int, array[int]] = defaultdict(lambda: array("q"))
        self._statement_trail: defaultdict[int, array[int]] = defaultdict(lambda: array("q"))
        self._statement_pcs: dict[bytes, frozenset[int]] = {}
        self._last_checkpoint_wall = 0.0
        self._copy_cost = 0.0
        self._observer = _Observer(self)
        self._base: Run | None = None
        self._checkpoints: list[Checkpoint] = []
        self._copyable = True  # False once a run could not be copied: checkpoints are then the start

    # ---- the adapter's side ----------------------------------------------------------------
    def start(self, stop_on_entry: bool) -> None:
        self._launch(Goal(0, "entry") if stop_on_entry else None, None)

    def set_breakpoints(self, locations: dict[tuple[int, int], list[Breakpoint]]) -> None:
        self._locations = locations
        self._tables = {}  # built again, per running code, on the world's thread

    def resume(self, kind: str = "continue", step: Step | None = None) -> None:
        with self._cv:
            if self.stop is None:
                return  # already running (two requests in a row): nothing to give
            self._command = ("resume", step)
            self._cv.notify_all()

    def pause(self) -> None:
        """Stop the world at its next moment. A world that is stopped and not yet told to go on
        has nothing to pause; one told to go on whose thread has not woken yet pauses at once."""
        with self._cv:
            if self.stop is not None and self._command is None:
                return
            self._pause = True
        self._update_special()

    def go_back(self, scan: Scan | None, goal: Goal | None) -> None:
        """Discard this run and reach an earlier moment (``goal``, or the last one ``scan`` finds)."""
        self._end_thread()
        self.ended = False
        self._launch(goal, scan)

    def terminate(self) -> None:
        self._end_thread()
        self.ended = True
        if self._base is not None:
            self._base.close()  # the PyBullet client every copy shares
            self._checkpoints.clear()

    @property
    def running(self) -> bool:
        return self.stop is None and not self.ended

    # ---- the world's side ------------------------------------------------------------------
    def previous(self, module: int, before: int, statement: bool) -> int:
        """The last moment before ``before`` when ``module`` was about to execute an instruction
        (``statement``: the first of a statement); 0 (the start) if there is none."""
        trail = (self._statement_trail if statement else self._trail).get(module)
        if not trail:
            return 0
        i = bisect_left(trail, before)
        return trail[i - 1] if i > 0 else 0

    def on_instruction(self, runtime: Any, frame: Frame) -> None:
        self.count += 1
        # the trail of every module, for going back one step without searching
        mid = runtime.module_id
        self._trail[mid].append(self.count)
        statements = self._statement_pcs.get(frame.code)
        if statements is None:
            statements = self._statement_pcs[frame.code] = frozenset(
                pc for pc in range(len(frame.code)) if self.code.is_statement(frame.code, pc))
        if frame.pc in statements:
            self._statement_trail[mid].append(self.count)
        if self._special:
            self._slow_instruction(runtime, frame)
            return
        table = self._tables.get(frame.code)
        if table is None:
            table = self._table_for(frame.code)
        if table and frame.pc in table:
            self._at_breakpoints(runtime, frame, table[frame.pc])

    def on_error(self, runtime: Any, message: str, code: bytes | None, pc: int | None) -> None:
        self.count += 1
        if self._moment_taken("error", runtime, None, code, pc):
            return
        if RUNTIME in self.filters:
            self._stop(Stop("exception", self.count, self._time(), runtime.module_id, None, code, pc,
                            text=f"module {runtime.module_id}: {message}"))

    def on_send(self, now: float, source: int, target: int, physical: int, packet: bytes,
                dropped: bool) -> None:
        self.count += 1
        if self._moment_taken("packet", None, None, None, None) or not dropped:
            return
        if PACKET in self.filters:
            self._stop(Stop("exception", self.count, self._time(), source,
                            text=f"a packet from module {source} to module {target} "
                                 f"(connector {physical}) was lost"))

    # ---- internals: the world's thread -----------------------------------------------------
    def _launch(self, goal: Goal | None, scan: Scan | None) -> None:
        self._command = None
        self._thread = threading.Thread(target=self._main, args=(goal, scan), name="rdcd-world", daemon=True)
        self._thread.start()

    def _end_thread(self) -> None:
        thread = self._thread
        if thread is None:
            return
        if thread.is_alive():
            self._give(("abort", None))
            self._pause = True  # a run in a long piece stops at its next moment
            self._update_special()
            thread.join()
        self._thread = None
        self._pause = False
        self._update_special()

    def _give(self, command: tuple[str, Any]) -> None:
        with self._cv:
            self._command = command
            self._cv.notify_all()

    def _first_run(self) -> Run:
        """The one run built from nothing; every later one is a copy of one of its checkpoints
        (in the physics world they all share its PyBullet client, closed by ``terminate``)."""
        run = self._new_run()
        self._base = run
        self.count, self._collided = 0, False
        self._checkpoint(run, force=True)
        return run

    def _new_run(self) -> Run:
        run = Run(self.program, self.structure, self.options)
        for runtime in run.runtimes.values():
            runtime.observer = self._observer
        run.world.network.on_send = self.on_send
        return run

    def _checkpoint(self, run: Run, force: bool = False) -> None:
        """Keep a copy of the run at this boundary (now and then: see ``CHECKPOINT_WALL_S``)."""
        last = self._checkpoints[-1] if self._checkpoints else None
        now = time.thread_time()
        if not force:
            # often enough that going back re-runs little, rarely enough that a run with the
            # debugger attached is hardly slower: the copies take at most 1/COPY_SHARE of the time
            wall = max(CHECKPOINT_WALL_S, COPY_SHARE * self._copy_cost)
            if last is None or self.count <= last.count or now - self._last_checkpoint_wall < wall:
                return
        if not self._copyable:
            if force and not self._checkpoints:
                self._checkpoints.append(Checkpoint(0, 0.0, False, None, None))
            return
        try:
            copied = copy.deepcopy(run, self._memo(run))
        except TypeError:
            # a run that cannot be copied (the firmware profile's controller keeps its scheduler in
            # generators): going back runs again from the start, which the deterministic world allows
            self._copyable = False
            self._checkpoints.append(Checkpoint(0, 0.0, False, None, None))
            return
        state = None
        if self.options.world != "lattice":
            import pybullet as pb

            state = pb.saveState(physicsClientId=run.world.client)
        self._checkpoints.append(Checkpoint(self.count, run.time, self._collided, copied, state))
        self._last_checkpoint_wall = time.thread_time()
        self._copy_cost = self._last_checkpoint_wall - now

    def _memo(self, run: Run) -> dict[int, Any]:
        """What a copy of a run shares with the original: the program, the engine, the observer;
        and the run's histories, which only ever grow by new items: copied one level deep (a new
        list of the same items), not item by item (most of a deep copy's time, and growing)."""
        world = run.world
        # and what the world never changes after it is built: geometry, ports, the role table
        static = [run.roles, getattr(world, "robot", None), getattr(world, "boxes", None),
                  getattr(world, "obstacle_ids", None), getattr(world, "_centres", None),
                  getattr(world, "_order", None), world.network._ports]  # noqa: SLF001
        sensors = getattr(world, "sensors", None)
        if sensors is not None:
            static += [sensors._rays, sensors.targets]  # noqa: SLF001
        for hal in world.hals.values():
            static += [getattr(hal, "_connected", None), getattr(hal, "_directions", None)]
        keep = (self, self._observer, self.program, self.structure, self.options, self.sink,
                *(item for item in static if item is not None))
        memo: dict[int, Any] = {id(k): k for k in keep}
        histories = [run.events, getattr(world, "events", None)]
        tracking = getattr(world, "tracking", None)
        if tracking is not None:
            histories += [tracking.trajectory, tracking.detections]
        for runtime in run.runtimes.values():
            histories += [runtime.event_log, runtime.errors, runtime.role_history, runtime.run_errors]
        for history in histories:
            if history is not None:
                memo[id(history)] = list(history)
        memo[id(memo)] = [*keep, *histories]  # deepcopy's keep-alive list: the ids stay valid
        return memo

    def _restore(self, before: int) -> Run:
        """A copy of the last checkpoint at or before moment ``before``, ready to go on."""
        shape = getattr(self.run.world, "shape", None) if self.run is not None else None
        if shape is not None and shape.rebuilds:
            # the physics world built its bodies again after a change of shape: the PyBullet
            # states saved in this client no longer fit its bodies. Start again in a new client
            # and go forward (the world is deterministic), keeping new checkpoints on the way.
            self._base.close()  # type: ignore[union-attr]
            self._checkpoints.clear()
            for trails in (self._trail, self._statement_trail):
                for trail in trails.values():
                    del trail[:]
            return self._first_run()
        cp = max((c for c in self._checkpoints if c.count <= before), key=lambda c: c.count)
        if cp.run is None:  # not copyable: a new run from the start
            run = self._new_run()
            self.count, self._collided = 0, False
            for trails in (self._trail, self._statement_trail):
                for trail in trails.values():
                    del trail[:]
            self._last_checkpoint_wall = time.thread_time()
            return run
        run = copy.deepcopy(cp.run, self._memo(cp.run))
        run.hook_events()
        if cp.state is not None:
            import pybullet as pb

            client = run.world.client
            pb.restoreState(stateId=cp.state, physicsClientId=client)
            for joint in run.world.joints.values():  # the motors are not part of a saved state
                if joint.joint is None:  # locked in a loop: no motor
                    continue
                pb.setJointMotorControl2(joint.body, joint.joint, pb.VELOCITY_CONTROL,
                                         targetVelocity=joint._command, force=JOINT_MAX_TORQUE,  # noqa: SLF001
                                         physicsClientId=client)
        self.count, self._collided = cp.count, cp.collided
        for trails in (self._trail, self._statement_trail):
            for trail in trails.values():
                del trail[bisect_right(trail, cp.count):]
        self._last_checkpoint_wall = time.thread_time()
        return run

    def _main(self, goal: Goal | None, scan: Scan | None) -> None:
        try:
            if self._base is None:
                run = self.run = self._first_run()
            else:
                if scan is not None:
                    goal = Goal(self._find(scan), goal.reason if goal else "step")
                run = self.run = self._restore(goal.count if goal is not None else 0)
            self._forward(run, goal)
        except Aborted:
            pass
        except Exception as e:  # a bug of the world or the adapter: said, not a silent hang
            self.ended = True
            self.sink.failed(f"the simulation failed: {type(e).__name__}: {e}")

    def _find(self, scan: Scan) -> int:
        """The last moment before ``scan.until`` that ``scan.wanted`` accepts (0: the start),
        searched from the checkpoint before it, then from earlier ones."""
        until = scan.until
        for cp in sorted((c for c in self._checkpoints if c.count < until), key=lambda c: -c.count):
            scan.until, scan.last = until, 0
            self._scan = scan
            self._update_special()
            run = self.run = self._restore(cp.count)
            try:
                while run.advance_chunk():
                    self._boundary(run)
            except _ScanDone:
                pass
            finally:
                self._scan = None
                self._update_special()
            if scan.last:
                return scan.last
            until = cp.count
        return 0

    def _forward(self, run: Run, goal: Goal | None) -> None:
        """Run on from the moment ``run`` is at (a boundary); stop at ``goal`` on the way."""
        self.stop = None
        self._goal = goal if goal is not None and goal.count > self.count else None
        self._update_special()
        if goal is not None and goal.count == self.count:
            self._stop(Stop(goal.reason, self.count, run.time))
        while run.advance_chunk():
            self._boundary(run)
            self._checkpoint(run)
        self.ended = True
        self.sink.ended(run)

    def _boundary(self, run: Run) -> None:
        """A moment between two pieces of the run (no module is running)."""
        self.count += 1
        if self._moment_taken("boundary", None, None, None, None):
            return
        if self._pause:
            self._stop(Stop("pause", self.count, self._time()))
        elif self._collision():
            self._stop(Stop("exception", self.count, self._time(), text="a collision with the obstacle"))

    def _moment_taken(self, kind: str, runtime: Any, frame: Frame | None, code: bytes | None,
                      pc: int | None) -> bool:
        """Goals and scans own the moment (True: nothing else happens at it)."""
        command = self._command
        if command is not None and command[0] == "abort":
            raise Aborted
        scan = self._scan
        if scan is not None:
            if self.count >= scan.until:
                raise _ScanDone
            if scan.wanted(kind, runtime, frame):
                scan.last = self.count
            return True
        goal = self._goal
        if goal is not None:
            if self.count == goal.count:
                self._goal = None
                self._update_special()
                module = runtime.module_id if runtime is not None else None
                hits = self._hit_ids(runtime, frame) if goal.reason == "breakpoint" else []
                self._stop(Stop(goal.reason, self.count, self._time(), module, frame, code, pc, hits))
            return True
        return False

    def _slow_instruction(self, runtime: Any, frame: Frame) -> None:
        if self._moment_taken("instruction", runtime, frame, None, None):
            return
        table = self._tables.get(frame.code)
        if table is None:
            table = self._table_for(frame.code)
        if table and frame.pc in table and self._at_breakpoints(runtime, frame, table[frame.pc]):
            return
        step = self._step
        if step is not None and self._step_done(step, runtime, frame):
            self._stop(Stop("step", self.count, self._time(), runtime.module_id, frame))
        elif self._pause:
            self._stop(Stop("pause", self.count, self._time(), runtime.module_id, frame))
        elif self._collision():
            self._stop(Stop("exception", self.count, self._time(), runtime.module_id, frame,
                            text="a collision with the obstacle"))

    def _hit_ids(self, runtime: Any, frame: Frame | None) -> list[int]:
        """The breakpoints (not log points) at this moment whose role and condition hold."""
        if runtime is None or frame is None:
            return []
        table = self._tables.get(frame.code)
        if table is None:
            table = self._table_for(frame.code)
        out = []
        for bp in table.get(frame.pc, ()):
            if bp.log is not None or (bp.role is not None
                                      and not runtime.roles.is_instance(runtime.role, bp.role)):
                continue
            try:
                if bp.condition is None or bp.condition.evaluate(self.names(runtime, frame, self.run)):
                    out.append(bp.id)
            except ExprError:
                continue
        return out

    def _step_done(self, step: Step, runtime: Any, frame: Frame) -> bool:
        if runtime.module_id != step.module:
            return False
        if step.instruction:
            return True
        if not self.code.is_statement(frame.code, frame.pc):
            return False
        if step.kind == "stepOut" or step.frame is None:
            return frame is not step.frame
        return frame is not step.frame or self.code.line_of(frame.code, frame.pc) != step.line

    def _collision(self) -> bool:
        if COLLISION not in self.filters or self._collided or self.run is None:
            return False
        tracking = getattr(self.run.world, "tracking", None)
        if tracking is not None and tracking.collided:
            self._collided = True
            return True
        return False

    def _table_for(self, code: bytes) -> dict[int, list[Breakpoint]]:
        table: dict[int, list[Breakpoint]] = {}
        locations = self._locations
        if locations:
            for index, base in self.code.places(code):
                for offset in range(base, base + len(code)):
                    found = locations.get((index, offset))
                    if found:
                        table.setdefault(offset - base, []).extend(found)
        self._tables[code] = table
        return table

    def _at_breakpoints(self, runtime: Any, frame: Frame, candidates: list[Breakpoint]) -> bool:
        names: dict[str, Any] | None = None
        hit: list[Breakpoint] = []
        for bp in candidates:
            if bp.role is not None and not runtime.roles.is_instance(runtime.role, bp.role):
                continue
            if bp.condition is not None or bp.log is not None:
                names = names if names is not None else self.names(runtime, frame, self.run)
            if bp.condition is not None:
                try:
                    if not bp.condition.evaluate(names):
                        continue
                except ExprError as e:
                    self.sink.output(f"breakpoint {bp.id}: condition {bp.condition.text!r}: {e}\n",
                                     "stderr")
                    continue
            bp.hits += 1
            if bp.hit_condition is not None and not _hit_ok(bp.hit_condition, bp.hits):
                continue
            if bp.log is not None:
                line = self.code.line_of(frame.code, frame.pc)
                self.sink.output(_interpolate(bp.log, names or {}) + "\n", "console", line)
                continue
            hit.append(bp)
        if not hit:
            return False
        functions = all(bp.kind == "function breakpoint" for bp in hit)
        reason = "function breakpoint" if functions else "breakpoint"
        self._stop(Stop(reason, self.count, self._time(), runtime.module_id, frame,
                        hit_ids=[bp.id for bp in hit]))
        return True

    def _stop(self, stop: Stop) -> None:
        self._step = None
        self._pause = False
        self._update_special()
        with self._cv:
            if self._command is not None and self._command[0] == "abort":
                raise Aborted
            self._command = None
            self.stop = stop
        self.sink.stopped(stop)
        with self._cv:
            while self._command is None:
                self._cv.wait()
            command, self._command = self._command, None
            self.stop = None
        if command[0] == "abort":
            self._command = command  # every later moment of this run ends it too
            raise Aborted
        self._step = command[1]
        self._update_special()

    def _time(self) -> float:
        return self.run.time if self.run is not None else 0.0

    def _update_special(self) -> None:
        aborting = self._command is not None and self._command[0] == "abort"
        self._special = bool(self._goal or self._scan or self._step or self._pause
                             or COLLISION in self.filters or aborting)


def _hit_ok(condition: tuple[str, int], hits: int) -> bool:
    op, n = condition
    if op == "%":
        return n > 0 and hits % n == 0
    return {">=": hits >= n, "==": hits == n, ">": hits > n, "<": hits < n, "<=": hits <= n}[op]


def _interpolate(template: str, names: dict[str, Any]) -> str:
    """A log message: ``{expression}`` parts are evaluated (``debug.expr``), the rest is kept."""
    from debug.expr import parse

    out, at = [], 0
    while at < len(template):
        start = template.find("{", at)
        if start < 0:
            out.append(template[at:])
            break
        end = template.find("}", start)
        if end < 0:
            out.append(template[at:])
            break
        out.append(template[at:start])
        try:
            out.append(_show(parse(template[start + 1:end]).evaluate(names)))
        except ExprError as e:
            out.append(f"<{e}>")
        at = end + 1
    return "".join(out)


def _show(value: Any) -> str:
    return "none" if value is None else str(value)
