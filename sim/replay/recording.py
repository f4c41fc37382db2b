"""The recording of a run, for the replay page: poses, roles, VM events, packets, detections.

A ``Recording`` is handed to ``sim.run.simulate``; it watches the world from outside, through
hooks that already exist or are off by default (DESIGN.md rule 4: the VM sees nothing new):
each runtime's ``on_event`` (chained after the report's own recorder), the network's ``on_send``,
the physics world's ``on_detection``, and the run loop, which it splits into sample intervals
(``advance`` of both worlds is whole physics steps / VM ticks, so splitting changes nothing).
Runs are seen by wrapping each runtime's ``_finish`` on the instance (the scheduler calls it
after every run with the task and its outcome): that gives the fragment and the pc; commands a
program sends, by wrapping its ``send_command`` (what the interpreter calls) the same way.

Poses: per sample and module, the centre (mm) and the rotation since the start of each of its
two hemispheres (unit quaternions, x 32767), quantised to int16 (``sim.replay.encode``).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sim.replay.sources import SourceIndex
from vm.interpreter import Outcome
from vm.lattice.structure import Structure
from vm.packets import ACK, COMMAND, NOTIFY, PROGRAM
from vm.roles import ANY_ROLE

ERROR = Outcome.ERROR

SAMPLE_HZ = 10.0
MAX_MODULE_SAMPLES = 600_000  # module × samples: beyond this the sample rate is lowered
MAX_EVENTS = 100_000
MAX_PACKETS = 300_000
PACKET_KINDS = {PROGRAM: "program", COMMAND: "command", NOTIFY: "notify", ACK: "ack"}
CHANNELS = 11  # x, y, z, then the quaternions (x, y, z, w) of the PLUS and MINUS hemispheres


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
    _sample: Callable[[], list[int]] | None = None
    _last_command: dict = field(default_factory=dict)
    _origins: dict = field(default_factory=dict)  # (module, body bytes) -> fragment it was stored from
    _context: tuple[tuple[int, int] | None, int] | None = None

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
        self._sample = physics_sampler(world, self.structure)
        self._attach_runtimes(runtimes, lambda: world.time)
        self._attach_network(world.network)
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
        self._sample = lattice_sampler(world, self.structure)
        self._attach_runtimes(world.runtimes, world.now)
        self._attach_network(world.network)
        self.sample(0.0)

    def sampled(self, advance: Callable[[float], None],
                clock: Callable[[], float]) -> Callable[[float], None]:
        """``advance`` in pieces of one sample interval, a sample after each."""
        interval = 1.0 / self.hz

        def run(duration: float) -> None:
            done = 0.0  # counted like sim.run._chunks: a piece too short for one step still ends
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
        self.times.append(round(t, 3))
        self.rows.append(self._sample())

    # ---- hooks -----------------------------------------------------------------------------
    def _attach_runtimes(self, runtimes: dict, clock: Callable[[], float]) -> None:
        self.runtimes = runtimes
        for mid, runtime in runtimes.items():
            previous = runtime.on_event

            def on_event(kind: str, detail: dict, mid: int = mid, runtime: Any = runtime,
                         previous: Any = previous) -> None:
                if previous is not None:
                    previous(kind, detail)
                if kind == "command":  # behaviours repeat the same command every tick: keep the changes
                    key = (detail.get("command"), detail.get("arg"))
                    if self._last_command.get(mid) == key:
                        return
                    self._last_command[mid] = key
                self._vm_event(clock(), mid, runtime, kind, detail)
            runtime.on_event = on_event
            send = getattr(runtime, "send_command", None)
            if send is not None:  # what a program calls to send a command (vm.interpreter.Machine)
                def send_command(role: int, command: int, arg: int, mid: int = mid, runtime: Any = runtime,
                                 send: Any = send) -> None:
                    where, line = self._running_pc(mid)
                    name = "any role" if role == ANY_ROLE else runtime.roles.name(role)
                    self._event(clock(), mid, "send", where, line,
                                f"sent {_command_name(command)} ({arg}) to {name}")
                    send(role, command, arg)
                runtime.send_command = send_command
            for name in ("handle_event", "install_command"):  # Machine methods storing a body
                method = getattr(runtime, name, None)
                if method is not None:
                    def install(*args: Any, mid: int = mid, method: Any = method) -> None:
                        self._installed(mid, args[-1])
                        method(*args)
                    setattr(runtime, name, install)
            finish = getattr(runtime, "_finish", None)
            if finish is None:  # a runtime without the scheduler's finish step: no run events
                continue

            def finished(task: Any, result: Any, mid: int = mid, finish: Any = finish,
                         ran: set[int] = set()) -> None:  # noqa: B006 - one set per module, on purpose
                slot = task.slot
                # fast path: repeating behaviours run every tick; their first run is the story
                if slot is None or task.frame is None or (id(slot) in ran and result.outcome is not ERROR):
                    finish(task, result)
                    return
                ran.add(id(slot))
                self._context = self._run_finished(clock(), mid, task, result)
                try:
                    finish(task, result)  # an error it reports is located at the run's pc
                finally:
                    self._context = None
            runtime._finish = finished

    def _attach_network(self, network: Any) -> None:
        def on_send(now: float, source: int, target: int, physical: int, packet: bytes,
                    dropped: bool) -> None:
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

    def _vm_event(self, t: float, mid: int, runtime: Any, kind: str, detail: dict) -> None:
        where, line = None, -1
        if kind == "handler":
            k = int(detail.get("event", -1))
            vec = runtime.store.vectors[k] if 0 <= k < len(runtime.store.vectors) else None
            if vec is not None:
                where, line = self._locate(mid, vec.slot.code, 0)
            text = f"handler of event {k} fired"
        elif kind == "role":
            where, line = self._running_pc(mid)
            text = f"role set to {detail.get('name')}"
        elif kind == "program":
            slot = next((s for s in reversed(runtime.store.slots) if s.ident == detail.get("id")), None)
            if slot is not None:
                where, line = self._locate(mid, slot.code, 0)
            name = self.sources.fragment_name(where)
            text = f"fragment {name} received and stored ({detail.get('size')} bytes)"
        elif kind == "command":
            where, line = self._running_pc(mid)
            text = f"command {_command_name(detail.get('command'))} ({detail.get('arg')}) executed"
        elif kind == "error":
            where, line = self._running_pc(mid)
            text = f"error: {detail.get('message')}"
        elif kind == "trace":
            where, line = self._running_pc(mid)
            text = f"trace: {detail.get('text')}"
        else:
            text = f"{kind}: {detail}"
        self._event(t, mid, kind, where, line, text)

    def _running_pc(self, mid: int) -> tuple[tuple[int, int] | None, int]:
        """The fragment and pc of the program running now on module ``mid``, if any."""
        if self._context is not None:
            return self._context
        frame = _running_frame()
        return self._locate(mid, frame.code, max(0, frame.pc - 1)) if frame else (None, -1)

    def _locate(self, mid: int, code: bytes, pc: int) -> tuple[tuple[int, int] | None, int]:
        return self.sources.locate(code, pc, self._origins.get((mid, bytes(code))))

    def _installed(self, mid: int, code: bytes) -> None:
        """A handler or command body stored by the program running now: remember its fragment."""
        frame = _running_frame()
        where = self._locate(mid, frame.code, 0)[0] if frame else None
        if where is not None:
            self._origins[(mid, bytes(code))] = where[0]

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


def _running_frame() -> Any:
    """The interpreter's frame of the program running now (rare events only: role changes,
    commands, installs, errors), found on the Python stack; None outside a run."""
    from vm.interpreter import Frame

    f = sys._getframe(2)
    for _ in range(12):
        if f is None:
            break
        frame = f.f_locals.get("frame")
        if isinstance(frame, Frame):
            return frame
        f = f.f_back
    return None


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
