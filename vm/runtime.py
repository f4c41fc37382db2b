"""One DCD-VM module: program store, scheduler, diffusion, commands, notifications, events.

A world creates ``ModuleRuntime(hal, role_table, module_id=...)`` per module, calls
``receive(physical_channel, packet)`` on delivery and ``step()`` every tick; the entry module gets
``inject(fragment)``. Observable: ``role``, ``position``, ``axis``, ``mapping`` (virtual→physical),
``errors`` [(t, message)], ``role_history`` [(t, role)], ``event_log`` [(t, kind, detail)] and
the optional hook ``on_event(kind, detail)``; kinds: "role", "handler" (an event handler fired: a
detection), "command" (a command executed here), "program" (a program stored and queued),
"error", "trace" (ACTIVATE_DEBUG).

Fault tolerance (dcd-vm.md §6), in two parts:
- delivery: every program, command and notify packet is sent with per-link acknowledgement and
  retransmission (``vm.runtime_link``), so a fragment crosses each link despite loss; a module
  whose slots or queue are full does not acknowledge a program, so it is offered again later;
  headers whose coordinates contradict the parity rule (corruption) are dropped unacknowledged.
  With ``checksum=True`` (all modules of a world must agree) every packet carries a CRC-8
  trailer (``vm.packets.seal``) and corrupted packets are dropped unacknowledged, so corruption
  is as harmless as loss; the default keeps the exact §2 format.
- at most once: a program is identified by (id, bytes) and a command packet by (id, role,
  command, argument); a module remembers the programs it has accepted (for ever) and the
  commands it has seen (for ``COMMAND_MEMORY`` seconds, as command ids wrap), so copies arriving
  through cycles, retries or delayed packets are acknowledged but never run again. Notifies carry
  a per-sender sequence number in the id; an older one never overwrites a newer role.

Scheduling: each ``step`` processes received packets, retransmits, fires event handlers, then
runs every due task once (at most 255 instructions per run; SLEEP and SLEEP_ROTATIONS keep the
frame and resume it when due, with a fresh instruction budget). Handlers run with the event number
as argument; a handler fires when its sensor sees an object, once per detection: it is re-armed
when the sensor clears or when a disabled event is enabled again.
"""

from __future__ import annotations

import random
from collections import deque
from collections.abc import Callable

from vm import navigation as nav
from vm.hal import ModuleHal
from vm.interpreter import Frame, Outcome, Result, run
from vm.isa.opcodes import (
    BUILTIN_COMMANDS,
    ROTATE_CCW,
    ROTATE_CW,
    ROTATE_DEGREES,
    ROTATE_TO,
    STOP,
    USER_COMMAND_BASE,
    USER_COMMAND_NUMBERS,
)
from vm.isa.verifier import verify
from vm.packets import (
    COMMAND,
    NOTIFY,
    PROGRAM,
    AckPacket,
    CommandPacket,
    NotifyPacket,
    PacketError,
    ProgramPacket,
    decode,
    header_bytes,
    make_header,
    unseal,
)
from vm.roles import RoleTable
from vm.runtime_link import Link
from vm.runtime_store import HANDLER, USER_COMMAND, Slot, Store, StoreFull, Task
from vm.runtime_store import PROGRAM as PROGRAM_SLOT

COMMAND_MEMORY = 30.0  # seconds a seen command packet is remembered
MAX_INBOX = 64
MAX_LOG = 10_000
EventHook = Callable[[str, dict[str, object]], None]


class ModuleRuntime:
    def __init__(self, hal: ModuleHal, role_table: RoleTable, *, module_id: int, seed: int = 0,
                 checksum: bool = False) -> None:
        self.hal = hal
        self.checksum = checksum
        self.roles = role_table
        self.module_id = module_id
        self.rng = random.Random(seed * 1_000_003 + module_id)
        self.role = 0
        self.position: tuple[int, int, int] | None = None
        self.axis: int | None = None
        self.mapping: tuple[int, ...] | None = None  # virtual → physical
        self._p2v: tuple[int, ...] = nav.IDENTITY
        self.errors: list[tuple[float, str]] = []
        self.role_history: list[tuple[float, int]] = []
        self.event_log: list[tuple[float, str, dict[str, object]]] = []
        self.on_event: EventHook | None = None
        self.neighbour_roles = [0] * 8  # by virtual channel
        self.store = Store()
        self.link = Link(hal, self.rng, checksum=checksum)
        self.led = 0
        self.programs_run = 0  # received or injected programs that started (each counted once)
        self.runs = 0  # every run started: repeats, handlers and user commands included
        self.bad_packets = 0
        self.duplicates = 0
        self._inbox: deque[tuple[int, bytes]] = deque()
        self._seen_programs: set[tuple[int, bytes]] = set()
        self._seen_commands: dict[tuple[int, int, int, int], float] = {}
        self._notify_seq: dict[int, int] = {}  # physical channel → last notify id
        self._reported: set[object] = set()
        self._next_inject_id = 1
        self._next_local_id = self.rng.randrange(256)
        self._notify_id = 0

    # ---- world interface -------------------------------------------------------------------
    def receive(self, physical_channel: int, packet: bytes) -> None:
        if len(self._inbox) >= MAX_INBOX:
            self._error("receive buffer full, packet dropped")
            return
        try:
            if isinstance(packet, int):  # bytes(n) would make n zero bytes
                raise TypeError("a packet is bytes")
            self._inbox.append((int(physical_channel), bytes(packet)))
        except (TypeError, ValueError, OverflowError):
            self.bad_packets += 1

    def needs_step(self, events: bool = True) -> bool:
        """Whether ``step`` has anything to do (received packets, retries, tasks, or — when
        ``events`` — installed event handlers to poll); a world may skip idle modules."""
        return bool(self._inbox or self.link.outbox or self.store.tasks
                    or (events and any(v is not None for v in self.store.vectors)))

    def stats(self) -> dict[str, int]:
        """Counters for reports: packets sent (with retries), retransmissions, duplicates..."""
        return {"sent": self.link.sent, "retransmissions": self.link.retransmissions,
                "given_up": self.link.given_up, "outbox_overflows": self.link.overflows,
                "duplicates": self.duplicates, "bad_packets": self.bad_packets,
                "programs_run": self.programs_run, "runs": self.runs, "errors": len(self.errors)}

    def inject(self, fragment: bytes) -> None:
        """Enter a fragment here; the first injection defines the frame (origin, NS, identity)."""
        if self.position is None:
            self._set_frame((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY)
        ident = self._next_inject_id
        self._next_inject_id = (ident + 1) & 0xFF
        try:
            if isinstance(fragment, int):  # bytes(n) would make n zero bytes
                raise TypeError("a fragment is bytes")
            code = bytes(fragment)
        except (TypeError, ValueError):
            self._error("inject: the fragment is not bytes")
            return
        self._accept_program(code, ident, None, None)

    def step(self) -> None:
        try:
            while self._inbox:
                self._handle_packet(*self._inbox.popleft())
            self.link.tick()
            self._expire_commands()
            self._check_events()
            self._run_tasks()
        except Exception as e:  # a VM bug must not crash the world: report it on this module
            self._error(f"internal error: {type(e).__name__}: {e}")

    # ---- packets ---------------------------------------------------------------------------
    def _handle_packet(self, ch: int, raw: bytes) -> None:
        if self.checksum:
            sealed = unseal(raw)
            if sealed is None:
                self.bad_packets += 1  # corrupted in transit: stay silent, the sender retries
                return
            raw = sealed
        p = decode(raw)
        if isinstance(p, PacketError) or not 0 <= ch <= 7:
            self.bad_packets += 1
            return
        if isinstance(p, AckPacket):
            self.link.on_ack(ch, p)
            return
        h = p.header
        if nav.axis_for_position(h.x, h.y, h.z) != h.r:
            self.bad_packets += 1  # corrupted header: stay silent, the sender retries
            return
        if self.position is None:
            self._set_frame((h.x, h.y, h.z), h.r, nav.virtual_to_physical(h.vch, ch))
        if isinstance(p, ProgramPacket):
            if self._accept_program(p.code, h.id, ch, h.vch):
                self.link.send_ack(ch, raw)
        elif isinstance(p, CommandPacket):
            self.link.send_ack(ch, raw)
            self._accept_command(p, ch)
        elif isinstance(p, NotifyPacket):
            self.link.send_ack(ch, raw)
            self._accept_notify(p, ch)

    def _accept_program(self, code: bytes, ident: int, ch: int | None, vch: int | None) -> bool:
        """Store and queue a program; False when it should be offered again later (no room)."""
        key = (ident, code)
        if key in self._seen_programs:
            self.duplicates += 1
            return True
        problems = verify(code)
        if problems:
            self._seen_programs.add(key)
            self._error(f"program {ident} rejected: {'; '.join(problems)}")
            return True
        ctx = (*self.position, self.axis, vch) if self.position and self.axis else None
        try:
            slot = self.store.add_slot(Slot(code, ident, PROGRAM_SLOT, ch, ctx))
            try:
                self.store.queue(Task(slot))
            except StoreFull:
                self.store.free_slot(slot)
                raise
        except StoreFull as e:
            self._error_once(("full", key), f"program {ident} not accepted: {e}")
            return False
        self._seen_programs.add(key)
        self._log("program", {"id": ident, "size": len(code)})
        return True

    def _accept_command(self, p: CommandPacket, ch: int) -> None:
        key = (p.header.id, p.role, p.command, p.argument & 0xFF)
        if key in self._seen_commands:
            self.duplicates += 1
            return
        self._seen_commands[key] = self.hal.now()
        self._flood_command(p.header.id, p.role, p.command, p.argument, exclude=ch)
        if self.roles.is_instance(self.role, p.role):
            self._queue_command(p.command, p.argument)

    def _accept_notify(self, p: NotifyPacket, ch: int) -> None:
        last = self._notify_seq.get(ch)
        if last is not None and not 0 < (p.header.id - last) & 0xFF < 128:
            return  # a duplicate or an older notify
        self._notify_seq[ch] = p.header.id
        self.neighbour_roles[self._p2v[ch]] = p.role

    # ---- sending ---------------------------------------------------------------------------
    def _send_all(self, type_: int, ident: int, body: bytes, exclude: int | None) -> None:
        if self.position is None or self.axis is None:
            return
        x, y, z = self.position
        for ch in sorted(self.hal.connected_channels()):
            if ch == exclude or not 0 <= ch <= 7:
                continue
            rx, ry, rz, raxis, rvch = nav.receiver(x, y, z, self.axis, self._p2v[ch])
            self.link.send(ch, header_bytes(make_header(type_, ident, rx, ry, rz, raxis, rvch)) + body)

    def _migrate(self, slot: Slot) -> None:
        ident = slot.ident
        if slot.kind != PROGRAM_SLOT:  # a handler or command spreading: a new program each time
            ident = self._local_id()
            self._seen_programs.add((ident, slot.code))
        self._send_all(PROGRAM, ident, slot.code, exclude=slot.in_physical)

    def _flood_command(self, ident: int, role: int, command: int, arg: int, exclude: int | None) -> None:
        self._send_all(COMMAND, ident, bytes((role & 0xFF, command & 0xFF, arg & 0xFF)), exclude)

    # ---- scheduler -------------------------------------------------------------------------
    def _check_events(self) -> None:
        for k, vec in enumerate(self.store.vectors):
            if vec is None:
                continue
            if not self.hal.proximity(k):
                vec.armed = True
                continue
            if not (vec.enabled and vec.armed) or any(t.slot is vec.slot for t in self.store.tasks):
                continue
            try:
                self.store.queue(Task(vec.slot, arg=k))
            except StoreFull as e:
                self._error(f"handler of event {k} not run: {e}")
                continue
            vec.armed = False
            self._log("handler", {"event": k})

    def _run_tasks(self) -> None:
        now = self.hal.now()
        for task in list(self.store.tasks):
            if task not in self.store.tasks or not self._due(task, now):
                continue
            task.wake_time = task.wake_turns = None
            if task.slot is None:
                self.store.tasks.remove(task)
                self._run_command(task.command or 0, task.arg)
                continue
            if task.frame is None:
                task.frame = Frame(task.slot.code, task.arg)
                self.runs += 1
                if task.slot.kind == PROGRAM_SLOT and not task.slot.started:
                    task.slot.started = True
                    self.programs_run += 1
            self._finish(task, run(task.frame, self))

    def _due(self, task: Task, now: float) -> bool:
        if task.wake_time is not None:
            return now >= task.wake_time
        if task.wake_turns is not None:
            return self.hal.joint_turns() >= task.wake_turns
        return True

    def _finish(self, task: Task, result: Result) -> None:
        slot = task.slot
        if result.outcome is Outcome.SLEEP:
            task.wake_time = self.hal.now() + 1.0
            return
        if result.outcome is Outcome.SLEEP_ROTATIONS:
            task.wake_turns = self.hal.joint_turns() + max(0, result.turns)
            return
        if result.outcome is Outcome.REPEAT:
            self.store.tasks.remove(task)
            task.frame = None
            self.store.tasks.append(task)
            return
        self.store.tasks.remove(task)
        if result.outcome is Outcome.MIGRATE and slot is not None:
            self._migrate(slot)
        elif result.outcome is Outcome.ERROR:
            self._error(f"program {slot.ident if slot else '?'}: {result.message}")
        self.store.release_after_run(slot)

    def _queue_command(self, command: int, arg: int) -> None:
        try:
            self.store.queue(Task(None, arg=arg, command=command))
        except StoreFull as e:
            self._error(f"command {command} not run: {e}")

    def _run_command(self, command: int, arg: int) -> None:
        """Execute a command here: built-ins drive the joint, user commands queue their program."""
        self._log("command", {"command": command, "arg": arg})
        hal = self.hal
        if command == ROTATE_CW:
            hal.rotate_continuously(abs(arg) or 1)
        elif command == ROTATE_CCW:
            hal.rotate_continuously(-(abs(arg) or 1))
        elif command == STOP:
            hal.stop_joint()
        elif command == ROTATE_DEGREES:
            hal.rotate_by(10.0 * arg)
        elif command == ROTATE_TO:
            hal.rotate_to(10.0 * arg)
        elif command >= USER_COMMAND_BASE:
            slot = self.store.command_slot(self.role, command - USER_COMMAND_BASE)
            if slot is not None:
                try:
                    self.store.queue(Task(slot, arg=arg, command=command))
                except StoreFull as e:
                    self._error(f"user command {command - USER_COMMAND_BASE} not run: {e}")
        else:
            self._error(f"unknown command {command}")

    # ---- Machine (what programs call) ------------------------------------------------------
    def axis_code(self) -> int:
        return self.axis or 0

    def coords(self) -> tuple[int, int, int]:
        return self.position or (0, 0, 0)

    def connected_virtual(self) -> int:
        mask = 0
        for ch in self.hal.connected_channels():
            if 0 <= ch <= 7:
                mask |= 1 << self._p2v[ch]
        return mask

    def facing(self, direction: int) -> int:
        return nav.channels_facing(self.axis, direction) if self.axis else 0

    def has_role(self, role: int) -> bool:
        return self.roles.is_instance(self.role, role)

    def connected_role(self, direction: int, role: int) -> int:
        mask = self.connected_virtual() & self.facing(direction)
        return sum(1 << v for v in range(8)
                   if mask >> v & 1 and self.roles.is_instance(self.neighbour_roles[v], role))

    def set_role_notify(self, role: int) -> None:
        if role != self.role:
            self.role = role
            self.role_history.append((self.hal.now(), role))
            self._log("role", {"role": role, "name": self.roles.name(role)})
        self._notify_id = (self._notify_id + 1) & 0xFF
        self._send_all(NOTIFY, self._notify_id, bytes((role & 0xFF,)), exclude=None)

    def handle_event(self, event: int, code: bytes) -> None:
        try:
            slot = self.store.add_slot(Slot(code, self._local_id(), HANDLER))
        except StoreFull as e:
            self._error(f"HANDLE_EVENT {event}: {e}")
            return
        self.store.set_vector(event, slot)

    def clear_event(self, event: int) -> None:
        if 0 <= event < 8:
            self.store.clear_vector(event)

    def enable_event(self, event: int, enabled: bool) -> None:
        vec = self.store.vectors[event] if 0 <= event < 8 else None
        if vec is not None:
            if enabled and not vec.enabled:
                vec.armed = True  # a new detection may start
            vec.enabled = enabled

    def send_command(self, role: int, command: int, arg: int) -> None:
        ident = self._local_id()
        self._seen_commands[(ident, role, command, arg & 0xFF)] = self.hal.now()
        self._flood_command(ident, role, command, arg, exclude=None)
        if self.roles.is_instance(self.role, role):
            self._queue_command(command, arg)

    def eval_command(self, command: int, arg: int) -> None:
        if command in BUILTIN_COMMANDS:
            self._run_command(command, arg)
        elif command >= USER_COMMAND_BASE:
            self._queue_command(command, arg)
        else:
            self._error(f"unknown command {command}")

    def install_command(self, role: int, command: int, code: bytes) -> None:
        k = command - USER_COMMAND_BASE
        if command not in USER_COMMAND_NUMBERS:
            self._error(f"INSTALL_COMMAND: {command} is not a user command 128..132")
            return
        targets = self.roles.roles_instance_of(role)
        if not targets:
            return
        try:
            slot = self.store.add_slot(Slot(code, self._local_id(), USER_COMMAND))
        except StoreFull as e:
            self._error(f"INSTALL_COMMAND {command}: {e}")
            return
        for r in targets:
            self.store.set_command(r, k, slot)

    def clear_command_queue(self, command: int) -> None:
        self.store.tasks = [t for t in self.store.tasks if not (t.command == command and t.frame is None)]

    def set_led(self, value: int) -> None:
        self.led = value
        self.hal.set_led(value)

    def trace(self, frame: Frame, text: str) -> None:
        self._log("trace", {"text": text})

    # ---- helpers ---------------------------------------------------------------------------
    def _local_id(self) -> int:
        self._next_local_id = (self._next_local_id + 1) & 0xFF
        return self._next_local_id

    def _set_frame(self, position: tuple[int, int, int], axis: int, mapping: tuple[int, ...]) -> None:
        self.position, self.axis, self.mapping = position, axis, mapping
        self._p2v = nav.invert(mapping)

    def _expire_commands(self) -> None:
        now = self.hal.now()
        if self._seen_commands:
            self._seen_commands = {k: t for k, t in self._seen_commands.items() if now - t < COMMAND_MEMORY}

    def _error(self, message: str) -> None:
        self.errors.append((self.hal.now(), message))
        del self.errors[:-MAX_LOG]
        self._log("error", {"message": message})

    def _error_once(self, key: object, message: str) -> None:
        if key not in self._reported:
            self._reported.add(key)
            self._error(message)

    def _log(self, kind: str, detail: dict[str, object]) -> None:
        self.event_log.append((self.hal.now(), kind, detail))
        del self.event_log[:-MAX_LOG]
        if self.on_event is not None:
            self.on_event(kind, detail)
