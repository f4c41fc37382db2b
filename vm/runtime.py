"""One DCD-VM module: program store, scheduler, diffusion, commands, notifications, events.

A world creates ``ModuleRuntime(hal, role_table, module_id=...)`` per module, calls
``receive(physical_channel, packet)`` on delivery and ``step()`` every tick; the entry module gets
``inject(fragment)``. Observable: ``role``, ``position``, ``axis``, ``mapping`` (virtual→physical),
``errors`` [(t, message)], ``run_errors`` (the errors of program runs with the code and pc),
``halted``, ``role_history`` [(t, role)], ``event_log`` [(t, kind, detail)] and
the optional hook ``on_event(kind, detail)`` (for the story of a run with code locations, attach a
``vm.observer.RuntimeObserver`` as ``observer`` instead); kinds: "role", "handler" (an event handler fired: a
detection), "command" (a command executed here), "program" (a program stored and queued),
"error", "trace" (ACTIVATE_DEBUG), "links" (the module's connections changed: connectors lost and
gained; what follows is ``vm.runtime_shape``).

Packets, diffusion and their fault tolerance (docs/vm.md) are the module's network side,
``vm.runtime_node.ModuleNode``; this module adds the scheduler and the ``vm.interpreter.Machine``
that programs run against.

Scheduling: each ``step`` processes received packets, retransmits, fires event handlers, then
runs every due task once (at most 255 instructions per run; SLEEP and SLEEP_ROTATIONS keep the
frame and resume it when due, with a fresh instruction budget). Handlers run with the event number
as argument; a handler fires when its sensor sees an object, once per detection: it is re-armed
when the sensor clears or when a disabled event is enabled again.

VM profile: ``target`` (vm.isa.targets) says which opcodes run, the limits, and the firmware's
quirks (docs/vm.md) that the scheduler and the network side reproduce: handlers that run with
argument 0 on every step while their sensor sees, ENABLE_EVENT toggling, a module that halts on
an instruction it does not know, no duplicate suppression, no acknowledgements, the UD 5/7
offsets. The default target is this project's corrected VM.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

from vm import navigation as nav
from vm.hal import ModuleHal
from vm.interpreter import Frame, Outcome, Result, run
from vm.isa.opcodes import (
    AGGREGATES,
    BUILTIN_COMMANDS,
    PUBLISHED_SLOTS,
    ROTATE_CCW,
    ROTATE_CW,
    ROTATE_DEGREES,
    ROTATE_TO,
    STOP,
    USER_COMMAND_BASE,
    USER_COMMAND_NUMBERS,
    WHERE_CHILDREN,
    WHERE_CONNECTOR,
    carried_data_offset,
    saturated,
    signed_byte,
)
from vm.isa.targets import DEFAULT, Target
from vm.packets import NOTIFY, VALUE, ValuePacket, encode, make_header
from vm.roles import RoleTable
from vm.runtime_node import MAX_LOG
from vm.runtime_shape import ShapeNode
from vm.runtime_store import HANDLER, LOCAL, RERUN, USER_COMMAND, Slot, StoreFull, Task
from vm.runtime_store import PROGRAM as PROGRAM_SLOT


@dataclass(frozen=True)
class RunError:
    """A program run that ended in an error (or halted the module): where, for reports."""

    t: float
    message: str
    code: bytes  # the code that was running (a fragment, or a handler / command body)
    pc: int | None  # offset of the failing instruction in ``code``
    halted: bool


class ModuleRuntime(ShapeNode):
    def __init__(self, hal: ModuleHal, role_table: RoleTable, *, module_id: int, seed: int = 0,
                 checksum: bool = False, target: Target = DEFAULT) -> None:
        super().__init__(hal, role_table, module_id=module_id, seed=seed, checksum=checksum, target=target)
        self.run_errors: list[RunError] = []
        self.handler_refires = 0  # firmware profile: handler runs after the first of a detection
        self.role_history: list[tuple[float, int]] = []
        self.led = 0
        self.programs_run = 0  # received or injected programs that started (each counted once)
        self.runs = 0  # every run started: repeats, handlers and user commands included
        self._notify_id = 0
        self._value_id = 0
        self._changed_in_run = False  # a value changed during the run in progress
        self._running_slot: Slot | None = None  # the program of the run in progress (LOAD/STORE_DATA)
        self._published: list[int | None] = [None] * PUBLISHED_SLOTS  # last value sent of each
        # (t, state, value) on every change: several writes of one state in one instant are one
        # change (the value at its end), and none when they give the value back (a compact
        # sequence's step code is computed in two writes on every run of its relay)
        self.state_history: list[tuple[float, int, int]] = []
        self._instant: tuple[float, int, int] | None = None  # (t, state, value before) of the last entry

    # ---- world interface -------------------------------------------------------------------
    def needs_step(self, events: bool = True) -> bool:
        """Whether ``step`` has anything to do (received packets, retries, tasks that are not waiting
        for a value, or — when ``events`` — installed event handlers to poll); a world may skip idle
        modules."""
        return not self.halted and bool(self._inbox or self.link.outbox
                                        or any(not t.waiting for t in self.store.tasks)
                                        or (events and any(v is not None for v in self.store.vectors))
                                        or self._lost_neighbour() or self.links_changed()
                                        or bool(self.held))

    def stats(self) -> dict[str, int]:
        """Counters for reports: packets sent (with retries), retransmissions, duplicates..."""
        return {"sent": self.link.sent, "retransmissions": self.link.retransmissions,
                "given_up": self.link.given_up, "outbox_overflows": self.link.overflows,
                "duplicates": self.duplicates, "bad_packets": self.bad_packets,
                "programs_run": self.programs_run, "runs": self.runs, "errors": len(self.errors),
                "handler_refires": self.handler_refires}

    def step(self) -> None:
        if self.halted:
            return
        try:
            self._watch_links()
            while self._inbox:
                self._handle_packet(*self._inbox.popleft())
            self.link.tick()
            self._forget_lost_neighbours()
            self._expire_commands()
            self._check_events()
            self._run_tasks()
        except Exception as e:  # a VM bug must not crash the world: report it on this module
            self._error(f"internal error: {type(e).__name__}: {e}")

    # ---- scheduler -------------------------------------------------------------------------
    def _check_events(self) -> None:
        refires = self.target.quirks.handler_refires_with_zero
        for k, vec in enumerate(self.store.vectors):
            if vec is None:
                continue
            if not self.hal.proximity(k):
                vec.armed = True
                continue
            if not vec.enabled or any(t.slot is vec.slot for t in self.store.tasks):
                continue
            if not (vec.armed or refires):
                continue
            try:
                # the firmware starts a handler with argument 0 and again on every step it sees
                self.store.queue(Task(vec.slot, arg=0 if refires else k))
            except StoreFull as e:
                self._error(f"handler of event {k} not run: {e}")
                continue
            if vec.armed:  # a detection: logged once, re-runs of the same detection are counted
                self._log("handler", {"event": k})
                if self.observer is not None:
                    self.observer.handler_fired(self, k, vec.slot)
            else:
                self.handler_refires += 1
            vec.armed = False

    def _run_tasks(self) -> None:
        now = self.hal.now()
        for task in list(self.store.tasks):
            if self.halted:
                return
            if task not in self.store.tasks or not self._due(task, now):
                continue
            task.wake_time = task.wake_turns = None
            if task.slot is None:
                self.store.tasks.remove(task)
                self._run_command(task.command or 0, task.arg)
                continue
            self._changed_in_run = False
            self._running_slot = task.slot
            if task.frame is None:
                task.frame = Frame(task.slot.code, task.arg)
                self.runs += 1
                if task.slot.kind == PROGRAM_SLOT and not task.slot.started:
                    task.slot.started = True
                    self.programs_run += 1
            if self.observer is None:
                self._finish(task, run(task.frame, self, self.target))
                continue
            self._running = task.frame  # observed: where the calls the program makes come from
            observer = self.observer
            before = partial(observer.before_instruction, self) if observer.instructions else None
            try:
                result = run(task.frame, self, self.target, before)
            finally:
                self._running = None
            self.observer.run_finished(self, task, result)
            self._finish(task, result)

    def _due(self, task: Task, now: float) -> bool:
        if task.waiting:
            return False
        if task.wake_action:
            result = self.hal.action_result()
            if result is None:
                return False
            task.wake_action = False
            if task.frame is not None:  # the action's answer: what its instruction pushes
                task.frame.stack.append(1 if result else 0)
            return True
        if task.wake_time is not None:
            return now >= task.wake_time
        if task.wake_turns is not None:
            return self.hal.joint_turns() >= task.wake_turns
        return True

    def _finish(self, task: Task, result: Result) -> None:
        slot = task.slot
        if slot is not None and slot.kind == RERUN and result.outcome in (Outcome.REPEAT, Outcome.WAIT):
            result = Result(Outcome.TERMINATE)  # a round runs each program once
        if result.outcome is Outcome.SLEEP:
            task.wake_time = self.hal.now() + 1.0
            return
        if result.outcome is Outcome.SLEEP_ROTATIONS:
            task.wake_turns = self.hal.joint_turns() + max(0, result.turns)
            return
        if result.outcome is Outcome.ACTION:
            task.wake_action = True
            return
        if result.outcome is Outcome.REPEAT:
            self.store.tasks.remove(task)
            task.frame = None
            self.store.tasks.append(task)
            return
        if result.outcome is Outcome.WAIT:
            # a run that changed a value runs again (its next run may read it), like END_REPEAT;
            # one that changed nothing waits until something else does
            task.frame = None
            task.waiting = not self._changed_in_run
            return
        self.store.tasks.remove(task)
        if result.outcome is Outcome.MIGRATE and slot is not None and slot.kind != RERUN:
            self._migrate(slot)
        elif result.outcome in (Outcome.ERROR, Outcome.HALT):
            self._run_error(task, result)
        self.store.release_after_run(slot)
        if slot is not None and slot.kind == PROGRAM_SLOT:
            self._keep(slot)
        elif slot is not None and slot.kind == RERUN:
            self._round_next()

    def _run_error(self, task: Task, result: Result) -> None:
        halted = result.outcome is Outcome.HALT
        message = f"program {task.slot.ident if task.slot else '?'}: {result.message}"
        if halted:
            message += "; module halted"
            self.halted = True
        code = task.slot.code if task.slot else b""
        self.run_errors.append(RunError(self.hal.now(), message, code, result.pc, halted))
        del self.run_errors[:-MAX_LOG]
        self._error(message, code, result.pc)

    def _run_command(self, command: int, arg: int) -> None:
        """Execute a command here: built-ins drive the joint, user commands queue their program."""
        self._log("command", {"command": command, "arg": arg})
        if self.observer is not None:
            self.observer.command_executed(self, command, arg, *self._where())
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
            elif self._holds and self.role != 0:  # its code has not arrived yet (vm.runtime_hold)
                self._hold(self.role, command, arg)
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

    def connected_physical(self) -> int:
        return sum(1 << ch for ch in self.hal.connected_channels() if 0 <= ch <= 7)

    def facing(self, direction: int) -> int:
        return nav.channels_facing(self.axis, direction) if self.axis else 0

    def has_role(self, role: int) -> bool:
        if self.in_round():  # the role taken in this round of discovery (vm.runtime_shape)
            return self.roles.is_instance(self._round.taken, role)  # type: ignore[union-attr]
        return self.roles.is_instance(self.role, role)

    def connected_role(self, direction: int, role: int) -> int:
        mask = self.connected_virtual() & self.facing(direction)
        return sum(1 << v for v in range(8)
                   if mask >> v & 1 and self.roles.is_instance(self.neighbour_roles[v], role))

    def set_role_notify(self, role: int) -> bool | None:
        """False: the run stops here (a round of discovery found the role the module plays)."""
        if self.in_round() and not self._round_role(role):
            return False
        if role == self.role == 0:
            return  # a module without a role has nothing new to announce (a re-check found none)
        if role != self.role:
            self.role = role
            self._values_changed()
            self.role_history.append((self.hal.now(), role))
            self._log("role", {"role": role, "name": self.roles.name(role)})
            if self.observer is not None:
                self.observer.role_set(self, role, *self._where())
            self._release_held()
        self._notify_id = (self._notify_id + 1) & 0xFF
        self._send_all(NOTIFY, self._notify_id, bytes((role & 0xFF,)), exclude=None)

    def handle_event(self, event: int, code: bytes) -> None:
        try:
            slot = self.store.add_slot(Slot(code, self._local_id(), HANDLER, role=self.role))
        except StoreFull as e:
            self._error(f"HANDLE_EVENT {event}: {e}")
            return
        self.store.set_vector(event, slot)
        if self.observer is not None:
            self.observer.handler_installed(self, event, slot, *self._where())

    def clear_event(self, event: int) -> None:
        if 0 <= event < 8:
            self.store.clear_vector(event)

    def enable_event(self, event: int, enabled: bool) -> None:
        vec = self.store.vectors[event] if 0 <= event < 8 else None
        if vec is not None:
            if enabled and self.target.quirks.enable_event_toggles:
                enabled = not vec.enabled  # the firmware flips the disabled flag
            if enabled and not vec.enabled:
                vec.armed = True  # a new detection may start
            vec.enabled = enabled

    def send_command(self, role: int, command: int, arg: int) -> None:
        if self.observer is not None:
            self.observer.command_sent(self, role, command, arg, *self._where())
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
        self._release_held()
        if self.observer is not None:
            self.observer.command_installed(self, role, command, slot, *self._where())

    def clear_command_queue(self, command: int) -> None:
        self.store.tasks = [t for t in self.store.tasks if not (t.command == command and t.frame is None)]

    def set_led(self, value: int) -> None:
        self.led = value
        self.hal.set_led(value)

    # ---- state (this project's extension) ---------------------------------------------------
    def load_state(self, index: int) -> int:
        return self.state[index]

    def _log_state(self, index: int, old: int, value: int) -> None:
        now, history = self.hal.now(), self.state_history
        if self._instant is not None and self._instant[:2] == (now, index) and history:
            before = self._instant[2]
            history.pop()
            if value == before:  # back to the value before this instant: no change
                self._instant = None
                return
            history.append((now, index, value))
            return
        self._instant = (now, index, old)
        history.append((now, index, value))
        del history[:-MAX_LOG]

    def store_state(self, index: int, value: int) -> None:
        old = self.state[index]
        self.state[index] = value
        if old != value:
            self._log_state(index, old, value)
            self._values_changed()
        if index < PUBLISHED_SLOTS and self._published[index] != value:
            self._published[index] = value
            self._publish(index, value)

    def _publish(self, index: int, value: int) -> None:
        if self.position is None or self.axis is None:
            return
        self._value_id = (self._value_id + 1) & 0xFF
        x, y, z = self.position
        for ch in sorted(self.hal.connected_channels()):
            if not 0 <= ch <= 7:
                continue
            rx, ry, rz, raxis, rvch = nav.receiver(x, y, z, self.axis, self._p2v[ch],
                                                   ud_offsets_swapped=self.target.quirks.ud_offsets_swapped)
            header = make_header(VALUE, self._value_id, rx, ry, rz, raxis, rvch)
            self.link.send(ch, encode(ValuePacket(header, index, ch == self.parent_channel, value)))

    def neighbour_values_of(self, gather: int, where: int) -> list[int]:
        """The values of published state ``gather & 7`` that the neighbours chosen by ``where``
        last sent (only neighbours still connected)."""
        index = gather & 7
        mask = self.connected_virtual()
        if where == WHERE_CHILDREN:
            mask &= sum(1 << v for v in range(8) if self.neighbour_is_child[v])
        elif where in nav.DIRECTIONS:
            mask &= self.facing(where)
        elif WHERE_CONNECTOR <= where < WHERE_CONNECTOR + 8:
            mask &= 1 << (where - WHERE_CONNECTOR)
        values = (self.neighbour_cache[v][index] for v in range(8) if mask >> v & 1)
        return [value for value in values if value is not None]

    def neighbour_values(self, gather: int, where: int) -> int:
        values = self.neighbour_values_of(gather, where)
        kind = AGGREGATES[(gather >> 4) & 3]
        if kind == "min":
            return min(values, default=127)
        if kind == "max":
            return max(values, default=-128)
        if kind == "count":
            return len(values)
        return saturated(sum(values))

    def command_code(self, command: int) -> bytes | None:
        """The code of user command ``command`` for the module's role (CONTINUE_COMMAND)."""
        if command not in USER_COMMAND_NUMBERS:
            return None
        slot = self.store.command_slot(self.role, command - USER_COMMAND_BASE)
        return slot.code if slot is not None else None

    def run_local(self, code: bytes) -> None:
        if any(s.kind == LOCAL and s.code == code for s in self.store.slots):
            return
        try:
            self.store.add_and_queue(Slot(code, self._local_id(), LOCAL))
        except StoreFull as e:
            self._error(f"RUN_LOCAL: {e}")

    def load_data(self) -> int:
        slot = self._running_slot
        at = carried_data_offset(slot.code) if slot is not None else None
        return signed_byte(slot.code[at]) if slot is not None and at is not None else 0

    def store_data(self, value: int) -> None:
        slot = self._running_slot
        at = carried_data_offset(slot.code) if slot is not None else None
        if slot is not None and at is not None:
            slot.code = slot.code[:at] + bytes((value & 0xFF,))

    # ---- connector and joint actions (structures that change) --------------------------------
    def start_action(self, kind: str, arg: int, code: bytes, pc: int) -> None:
        """CONNECT, DISCONNECT, TURN_QUARTERS: ask the world; the run waits for its answer. The
        log entry names the code and the instruction, for the report's source line."""
        self._log("action", {"action": kind, "arg": arg, "code": code, "pc": pc})
        if self.observer is not None:
            self.observer.action_started(self, kind, arg, code, pc)
        if kind == "turn":
            self.hal.rotate_quarters(arg)
        elif kind == "connect":
            self.hal.connect(arg)
        else:
            self.hal.disconnect(arg)

    def is_connected(self, connector: int) -> bool:
        return 0 <= connector <= 7 and self.hal.is_connected(connector)

    def is_aligned(self, connector: int) -> bool:
        return 0 <= connector <= 7 and self.hal.other_connector_nearby(connector)

    def _values_changed(self) -> None:
        self._changed_in_run = True
        for task in self.store.tasks:
            task.waiting = False

    def _lost_neighbour(self) -> bool:
        """Whether a neighbour whose values this module keeps is no longer attached."""
        if not self._keeps_values:
            return False
        connected = self.connected_virtual()
        return any(not connected >> v & 1 and (self.neighbour_is_child[v] or any(
            value is not None for value in self.neighbour_cache[v])) for v in range(8))

    def _forget_lost_neighbours(self) -> None:
        """A neighbour that is no longer attached: its values and its child mark are forgotten."""
        if not self._keeps_values:
            return
        connected = self.connected_virtual()
        for v in range(8):
            if not connected >> v & 1 and (self.neighbour_is_child[v] or any(
                    value is not None for value in self.neighbour_cache[v])):
                self.neighbour_cache[v] = [None] * PUBLISHED_SLOTS
                self.neighbour_is_child[v] = False
                self._values_changed()

    def _take_role(self, role: int) -> None:
        self.set_role_notify(role)

    def trace(self, frame: Frame, text: str) -> None:
        self._log("trace", {"text": text})
        if self.observer is not None:
            self.observer.traced(self, text, frame.code, frame.at)
