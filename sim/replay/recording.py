"""The recording of a run, for the replay page: poses, roles, VM events, packets, detections.

A ``Recording`` is handed to ``sim.run.simulate``; it watches the world from outside, through
hooks that are off by default (docs/architecture.md rule 4: the VM sees nothing new): each runtime's
``observer`` (``vm.observer``: fragments stored and run with their code and pc, roles, handlers,
commands, errors), the network's ``on_send``, the physics world's ``on_detection``, and the run
loop, which it splits into sample intervals (``advance`` of both worlds is whole physics steps /
VM ticks, so splitting changes nothing).

Poses: per sample and module, the centre (mm), the rotation since the start of each of its
two hemispheres (unit quaternions, x 32767), quantised to int16 (``sim.replay.encode``), and
whether the module is in the world then. Structures change (docs/replay.md): the modules are
every module of the start structure and every module an outside change attaches (``specs``: each
as it first appears); a module not yet attached, or taken away, is absent (its pose is the
nearest one it had, so nothing flies in from the origin). ``links`` is every latch that opened
or closed, [t, a, a's connector, b, b's connector, 1 latched / 0 unlatched], from the run's
structure; the structure's events (connect, rotation, split, outside change...) are events too,
placed on the source line of the action that caused them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sim.replay.changes import describe_change
from sim.replay.sources import SourceIndex
from vm.interpreter import Outcome
from vm.isa.opcodes import BY_OPCODE, PUSH_SMALL_BASE
from vm.lattice.structure import Structure
from vm.observer import RuntimeObserver
from vm.packets import ACK, COMMAND, NOTIFY, PROGRAM
from vm.roles import ANY_ROLE

ERROR, HALT = Outcome.ERROR, Outcome.HALT

SAMPLE_HZ = 10.0
MAX_MODULE_SAMPLES = 600_000  # module × samples: beyond this the sample rate is lowered
MAX_EVENTS = 100_000
MAX_PACKETS = 300_000
PACKET_KINDS = {PROGRAM: "program", COMMAND: "command", NOTIFY: "notify", ACK: "ack"}
# x, y, z, the quaternions (x, y, z, w) of the PLUS and MINUS hemispheres, then 1 present / 0 absent
CHANNELS = 12
PRESENT = 11
# the structure's events a module's own action caused (sim.run._ACTION_RESULTS): on its source line
ACTION_RESULTS = frozenset({"connect", "disconnect", "connect_failed", "disconnect_failed", "rotation_start",
                            "rotation_end", "rotation_failed"})


@dataclass
class Recording:
    structure: Structure
    sources: SourceIndex
    duration: float
    hz: float = SAMPLE_HZ
    notes: list[str] = field(default_factory=list)
    times: list[float] = field(default_factory=list)
    rows: list[list[int]] = field(default_factory=list)  # one per sample: CHANNELS ints per module
    events: list[list[Any]] = field(default_factory=list)  # [t, module, kind, fragment, pc, line, text]
    packets: list[tuple[float, int, int, int, int, int, bool]] = field(default_factory=list)
    world: str = ""
    dropped_events: int = 0
    dropped_packets: int = 0
    runtimes: dict = field(default_factory=dict)
    ids: list[int] = field(default_factory=list)  # every module that is ever in the world, sorted
    specs: dict = field(default_factory=dict)  # module -> its ModuleSpec when it first appears
    links: list[list[int | float]] = field(default_factory=list)  # [t, a, a_physical, b, b_physical, on]
    _live: Any = None  # the run's structure (the one that changes)
    _version: int = -1
    _latched: set = field(default_factory=set)
    _actions: dict = field(default_factory=dict)  # module -> where its last connector/joint action is
    _watched: set = field(default_factory=set)  # modules whose runtime has a _Watcher
    _world_runtimes: Any = None
    _clock: Any = None
    _sample: Callable[[], list[int]] | None = None
    _last_command: dict = field(default_factory=dict)
    _origins: dict = field(default_factory=dict)  # (module, body bytes) -> fragment it was stored from

    def __post_init__(self) -> None:
        n = max(1, len(self.structure.modules))
        wanted = self.duration * self.hz * n
        if wanted > MAX_MODULE_SAMPLES:
            # a whole number of 0.1-s intervals: whole physics steps and VM ticks, as before
            self.hz = SAMPLE_HZ / math.ceil(wanted / MAX_MODULE_SAMPLES)
            self.notes.append(f"long run: poses sampled every {1 / self.hz:.2g} s instead of "
                              f"{1 / SAMPLE_HZ:g} s (at most {MAX_MODULE_SAMPLES:,} module samples)")

    # ---- attaching -------------------------------------------------------------------------
    def attach_physics(self, world: Any, runtimes: dict) -> None:
        from sim.replay.poses import physics_sampler

        self.world = "physics"
        self._modules(world)
        self._sample = physics_sampler(world, self.ids)
        self._attach_runtimes(runtimes, lambda: world.time)
        self._attach_network(world.network)
        self._attach_changes(world, lambda: world.time)
        previous = world.on_detection

        def detected(mid: int, k: int) -> None:
            if previous is not None:
                previous(mid, k)
            self._event(world.time, mid, "sensor", None, -1, f"sensor {k} sees an obstacle")
        world.on_detection = detected
        self.sample(0.0)

    def attach_lattice(self, world: Any) -> None:
        from sim.replay.poses import lattice_sampler

        self.world = "lattice"
        self._modules(world)
        self._sample = lattice_sampler(world, self.ids, self.specs)
        self._attach_runtimes(world.runtimes, world.now)
        self._attach_network(world.network)
        self._attach_changes(world, world.now)
        self.sample(0.0)

    def sampled(self, advance: Callable[[float], None],
                clock: Callable[[], float]) -> Callable[[float], None]:
        """``advance`` in pieces of one sample interval, a sample after each."""
        interval = 1.0 / self.hz

        def run(duration: float) -> None:
            done = 0.0  # counted like sim.run.Run.advance_chunk: a piece too short for one step still ends
            while done < duration - 1e-9:
                step = min(interval, duration - done)
                advance(step)
                done += step
                self.sample(clock())
        return run

    def sample(self, t: float) -> None:
        if self._sample is None:
            return
        if self.times and round(t, 3) <= self.times[-1]:
            return
        self._adopt()
        self.times.append(round(t, 3))
        self.rows.append(self._sample())
        self._follow_links(round(t, 3))

    def filled_rows(self) -> list[list[int]]:
        """The rows with each absent module's pose set to the nearest pose it has while present
        (before it is attached: its first one), so that the viewer's interpolation stays put."""
        rows = [list(r) for r in self.rows]
        for i in range(len(self.ids)):
            first = next((r for r in rows if r[i * CHANNELS + PRESENT]), None)
            if first is None:
                continue
            pose = first[i * CHANNELS:i * CHANNELS + PRESENT]
            for r in rows:
                if r[i * CHANNELS + PRESENT]:
                    pose = r[i * CHANNELS:i * CHANNELS + PRESENT]
                else:
                    r[i * CHANNELS:i * CHANNELS + PRESENT] = pose
        return rows

    # ---- structures that change ------------------------------------------------------------
    def _modules(self, world: Any) -> None:
        """Every module that will ever be in the world: the start's and the attached ones."""
        from vm.lattice.structure import ModuleSpec

        self._live = world.structure
        self.specs = dict(self.structure.modules)
        for c in getattr(world, "outside", []):
            if c.kind == "attach" and c.module not in self.specs:
                self.specs[c.module] = ModuleSpec(c.module, c.cell, c.axis, c.mount)
        self.ids = sorted(self.specs)

    def _follow_links(self, t: float) -> None:
        live = self._live
        if live is None or live.version == self._version:
            return
        self._version = live.version
        now = {(k.a, k.a_physical, k.b, k.b_physical) for k in live.links()}
        for link in sorted(self._latched - now):
            self.links.append([t, *link, 0])
        for link in sorted(now - self._latched):
            self.links.append([t, *link, 1])
        self._latched = now

    def _attach_changes(self, world: Any, clock: Callable[[], float]) -> None:
        """The structure's events (world.on_change); the runtimes of modules attached later are
        watched from the next sample or structure event on (``_adopt``)."""
        previous = world.on_change

        def changed(t: float, mid: int, kind: str, detail: dict[str, Any]) -> None:
            if previous is not None:
                previous(t, mid, kind, detail)
            self._adopt()
            where, line = self._actions.get(mid, (None, -1)) if kind in ACTION_RESULTS else (None, -1)
            self._event(t, mid, kind, where, line, describe_change(kind, detail))
        world.on_change = changed
        self._world_runtimes = world.runtimes
        self._clock = clock

    def _adopt(self) -> None:
        """Watch the runtimes of modules attached since (their observer is not set yet)."""
        runtimes = self._world_runtimes
        if runtimes is None or len(runtimes) == len(self._watched):
            return
        for mid, runtime in runtimes.items():
            if mid not in self._watched and getattr(runtime, "observer", None) is None:
                runtime.observer = _Watcher(self, mid, self._clock)
            self._watched.add(mid)

    # ---- hooks -----------------------------------------------------------------------------
    def _attach_runtimes(self, runtimes: dict, clock: Callable[[], float]) -> None:
        self.runtimes = runtimes
        for mid, runtime in runtimes.items():
            if getattr(runtime, "observer", None) is not None:
                raise ValueError(f"module {mid} is already observed")
            runtime.observer = _Watcher(self, mid, clock)
            self._watched.add(mid)

    def _attach_network(self, network: Any) -> None:
        def on_send(now: float, source: int, target: int, physical: int, packet: bytes,
                    dropped: bool) -> None:
            if target not in self._watched:
                self._adopt()  # a module attached a moment ago: watched before its first packet
            if len(self.packets) >= MAX_PACKETS:
                self.dropped_packets += 1
                return
            kind = packet[0] if packet else 0
            self.packets.append((now, source, target, physical, len(packet), kind, dropped))
        network.on_send = on_send

    def _event(self, t: float, mid: int, kind: str, where: tuple[int, int] | None, line: int,
               text: str) -> None:
        if len(self.events) >= MAX_EVENTS:
            self.dropped_events += 1
            return
        fragment, pc = where if where else (-1, -1)
        self.events.append([round(t, 3), mid, kind, fragment, pc, line, text])

    def _locate(self, mid: int, code: bytes, pc: int) -> tuple[tuple[int, int] | None, int]:
        return self.sources.locate(code, pc, self._origins.get((mid, bytes(code))))

    def _at(self, mid: int, code: bytes | None, pc: int | None) -> tuple[tuple[int, int] | None, int]:
        """Where the instruction at ``pc`` of the running ``code`` is (nothing runs: nowhere). An event
        is placed on the last byte of its instruction, as recordings always have: the same line."""
        if code is None or pc is None:
            return None, -1
        return self._locate(mid, code, pc + _size(code, pc) - 1)

    def _installed(self, mid: int, body: bytes, code: bytes | None) -> None:
        """A handler or command body stored by the running ``code``: remember its fragment."""
        where = self._locate(mid, code, 0)[0] if code is not None else None
        if where is not None:
            self._origins[(mid, bytes(body))] = where[0]

    def _run_finished(self, t: float, mid: int, task: Any, result: Any) -> tuple[Any, int]:
        """A run event for the first run of a slot on a module, or a run that ended in an error."""
        where, line = self._locate(mid, task.slot.code, max(0, task.frame.pc - 1))
        name = self.sources.fragment_name(where)
        pc = where[1] if where else -1
        self._event(t, mid, "run", where, line, f"fragment {name} ran to pc {pc}: {result.outcome.value}")
        return where, line

    # ---- results ---------------------------------------------------------------------------
    def stored_fragments(self) -> dict[int, list[str]]:
        out = {}
        for mid, runtime in self.runtimes.items():
            out[mid] = [self._slot_name(mid, slot) for slot in runtime.store.slots]
        return out

    def _slot_name(self, mid: int, slot: Any) -> str:
        """A stored slot as the user knows it: its fragment, and what part of it when a piece."""
        where, _ = self._locate(mid, slot.code, 0)
        name = self.sources.fragment_name(where)
        kind = getattr(slot, "kind", "program")
        return name if kind == "program" else f"{name} ({kind})"

    def finish_notes(self) -> list[str]:
        notes = list(self.notes)
        if self.dropped_events:
            notes.append(f"{self.dropped_events:,} events after the first {MAX_EVENTS:,} are not shown")
        if self.dropped_packets:
            notes.append(f"{self.dropped_packets:,} packets after the first {MAX_PACKETS:,} are not shown")
        return notes


class _Watcher(RuntimeObserver):
    """What one module's runtime tells the recording (vm.observer)."""

    def __init__(self, recording: Recording, mid: int, clock: Callable[[], float]) -> None:
        self.rec, self.mid, self.clock = recording, mid, clock
        self.ran: set[Any] = set()  # slots whose first run is recorded (freed ones are dropped)
        self.failed: tuple[tuple[int, int] | None, int] | None = None  # where the run reporting an error is

    def program_stored(self, runtime: Any, slot: Any) -> None:
        where, line = self.rec._locate(self.mid, slot.code, 0)
        name = self.rec.sources.fragment_name(where)
        self.rec._event(self.clock(), self.mid, "program", where, line,
                        f"fragment {name} received and stored ({len(slot.code)} bytes)")

    def run_finished(self, runtime: Any, task: Any, result: Any) -> None:
        # repeating behaviours run every tick: the first run of a slot (and every error) is the story
        outcome = result.outcome
        if task.slot in self.ran and outcome is not ERROR:
            if outcome is HALT:
                self.failed = (None, -1)
            return
        if len(self.ran) >= 64:  # a freed slot never runs again: forget those
            self.ran.intersection_update(runtime.store.slots)
        self.ran.add(task.slot)
        where = self.rec._run_finished(self.clock(), self.mid, task, result)
        if outcome is ERROR or outcome is HALT:
            self.failed = where  # the error the runtime reports next is this run's: located here

    def role_set(self, runtime: Any, role: int, code: bytes | None, pc: int | None) -> None:
        where, line = self.rec._at(self.mid, code, pc)
        self.rec._event(self.clock(), self.mid, "role", where, line,
                        f"role set to {runtime.roles.name(role)}")

    def handler_installed(self, runtime: Any, event: int, slot: Any, code: bytes | None,
                          pc: int | None) -> None:
        self.rec._installed(self.mid, slot.code, code)

    def command_installed(self, runtime: Any, role: int, command: int, slot: Any, code: bytes | None,
                          pc: int | None) -> None:
        self.rec._installed(self.mid, slot.code, code)

    def handler_fired(self, runtime: Any, event: int, slot: Any) -> None:
        where, line = self.rec._locate(self.mid, slot.code, 0)
        self.rec._event(self.clock(), self.mid, "handler", where, line, f"handler of event {event} fired")

    def command_sent(self, runtime: Any, role: int, command: int, arg: int, code: bytes | None,
                     pc: int | None) -> None:
        where, line = self.rec._at(self.mid, code, pc)
        name = "any role" if role == ANY_ROLE else runtime.roles.name(role)
        self.rec._event(self.clock(), self.mid, "send", where, line,
                        f"sent {_command_name(command)} ({arg}) to {name}")

    def command_executed(self, runtime: Any, command: int, arg: int, code: bytes | None,
                         pc: int | None) -> None:
        key = (command, arg)  # behaviours repeat the same command every tick: keep the changes
        if self.rec._last_command.get(self.mid) == key:
            return
        self.rec._last_command[self.mid] = key
        where, line = self.rec._at(self.mid, code, pc)
        self.rec._event(self.clock(), self.mid, "command", where, line,
                        f"command {_command_name(command)} ({arg}) executed")

    def error(self, runtime: Any, message: str, code: bytes | None, pc: int | None) -> None:
        if self.failed is not None:
            (where, line), self.failed = self.failed, None
        else:
            where, line = self.rec._at(self.mid, code, pc)
        self.rec._event(self.clock(), self.mid, "error", where, line, f"error: {message}")

    def action_started(self, runtime: Any, kind: str, arg: int, code: bytes, pc: int) -> None:
        # the structure's event that answers it is placed on this instruction's line
        self.rec._actions[self.mid] = self.rec._at(self.mid, code, pc)

    def traced(self, runtime: Any, text: str, code: bytes | None, pc: int | None) -> None:
        where, line = self.rec._at(self.mid, code, pc)
        self.rec._event(self.clock(), self.mid, "trace", where, line, f"trace: {text}")


def _size(code: bytes, pc: int) -> int:
    """Bytes of the instruction at ``pc`` (1 for a push or an unknown byte)."""
    op = code[pc] if 0 <= pc < len(code) else 0
    ins = BY_OPCODE.get(op) if op < PUSH_SMALL_BASE else None
    return ins.size if ins is not None else 1


def _command_name(command: Any) -> str:
    from vm.isa.opcodes import ROTATE_CCW, ROTATE_CW, ROTATE_DEGREES, ROTATE_TO, STOP, USER_COMMAND_BASE

    names = {ROTATE_CW: "rotate clockwise", ROTATE_CCW: "rotate counter-clockwise", STOP: "stop",
             ROTATE_DEGREES: "rotate by", ROTATE_TO: "rotate to"}
    if isinstance(command, int) and command >= USER_COMMAND_BASE:
        return f"user command {command - USER_COMMAND_BASE}"
    return names.get(command, str(command))


def quantise_quaternion(q: tuple[float, float, float, float]) -> list[int]:
    x, y, z, w = q
    if w < 0:  # q and -q are one rotation: keep w >= 0 so deltas stay small
        x, y, z, w = -x, -y, -z, -w
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    return [round(c / n * 32767) for c in (x, y, z, w)]

