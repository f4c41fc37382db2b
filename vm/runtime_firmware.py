"""The ATRON firmware's DCD-VM controller, as the ``original`` VM profile runs it (docs/firmware.md).

A target whose quirks say ``firmware_controller`` runs each module as the firmware of 2007 does,
step for step: one program store of 10 slots each carrying the context (x, y, z, axis, incoming
virtual and physical channel, id) of the packet that brought it, one task queue of 10 entries (9
usable), and a main loop that, once per scheduler step, looks at the proximity sensors of the
enabled event handlers (running the first handler whose sensor sees an object, at once, with
argument 0) and then runs at most one task. ``SLEEP`` and ``SLEEP_ROTATIONS`` block the whole
module, and so do event handlers, user commands and the commands a module sends itself, which run
inline. Packets are handled the moment they arrive, also while the module is blocked: programs are
stored and queued, commands queued, notifies noted. Nothing is acknowledged, nothing suppresses
duplicates, and every error the firmware reports stops the module for good. The entry module first
runs the loader (``dcd_action``): 8 s before each fragment, which it sends to its neighbours
without running it; its scheduler starts after the last one.

The blocking parts are Python generators: ``yield STEP`` waits for the next scheduler step,
``yield t`` for the first step at or after time ``t``. ``vm.runtime.ModuleRuntime`` supplies the
world interface, the logs and reports this class fills in.
"""

from __future__ import annotations

from collections.abc import Generator
from dataclasses import dataclass

from vm import navigation as nav
from vm.hal import ModuleHal
from vm.isa.opcodes import BY_OPCODE
from vm.isa.targets import DEFAULT, Target
from vm.packets import COMMAND, NOTIFY, PROGRAM
from vm.roles import ANY_ROLE, RoleTable
from vm.runtime import ModuleRuntime, RunError
from vm.runtime_node import MAX_LOG

STEP = -1.0  # yielded: resume at the next scheduler step
SLOTS = 10  # MAX_N_STORED_PROGRAMS
QUEUE = 10  # MAX_N_ENQUEUED_TASKS: a ring of 10, so 9 tasks at most
MAX_STACK = 5
MAX_INSTRUCTIONS = 100  # a run ends in error on the 102nd instruction
MAX_ROLES = 15
ROLE_COMMANDS = 5
NONE = 255  # no vector, no command
DISABLED = 128
LOAD_DELAY_S = 8.0  # dcd_action: before each fragment
SLEEP_S = 1.0
TASK_INTERPRET, TASK_COMMAND = 1, 2
NS, EW, UD = nav.NORTH_SOUTH, nav.EAST_WEST, nav.UP_DOWN
NORTH, EAST, WEST, UP, DOWN = 6, 4, 5, 8, 9

# dcdError.h: the firmware's error numbers
ERRORS = {1: "program store full", 2: "task queue full", 3: "unknown message", 5: "illegal receiver rotation",
          6: "illegal virtual channel", 7: "stack overflow", 9: "unknown instruction",
          11: "instruction count exceeded", 12: "illegal connection direction", 13: "illegal axis direction",
          18: "illegal command install", 19: "illegal function", 21: "illegal argument index"}

Wait = Generator[float, None, int]


class Halt(Exception):
    """report_error: the firmware stops the module (it never returns)."""


@dataclass
class Context:
    x: int = 0
    y: int = 0
    z: int = 0
    r: int = NS
    in_vch: int = 0
    in_pch: int = 0
    program_id: int = 0


@dataclass
class Stored:
    context: Context
    code: bytes = b""


@dataclass
class FwTask:
    kind: int
    discard: bool = False
    slot: int = 0  # TASK_INTERPRET
    arg: int = 0
    role: int = 0  # TASK_COMMAND: the packet's fields
    command: int = 0
    argument: int = 0
    pch: int = 0
    x: int = 0
    y: int = 0
    z: int = 0
    r: int = 0
    vch: int = 0
    packet_id: int = 0


def s8(v: int) -> int:
    v &= 0xFF
    return v - 256 if v > 127 else v


# navigation.c: compute_receiver_coordinates, per axis and virtual channel: (dx, dy, dz, axis, receiver vch)
_RECEIVER = {
    NS: [(0, 1, 1, UD, 6), (-1, 1, 0, EW, 3), (0, 1, -1, UD, 2), (1, 1, 0, EW, 7),
         (0, -1, 1, UD, 4), (-1, -1, 0, EW, 1), (0, -1, -1, UD, 0), (1, -1, 0, EW, 5)],
    EW: [(1, 0, 1, UD, 7), (1, 1, 0, NS, 5), (1, 0, -1, UD, 3), (1, -1, 0, NS, 1),
         (-1, 0, 1, UD, 5), (-1, 1, 0, NS, 7), (-1, 0, -1, UD, 1), (-1, -1, 0, NS, 3)],
    UD: [(0, 1, 1, NS, 6), (1, 0, 1, EW, 6), (0, -1, 1, NS, 2), (-1, 0, 1, EW, 2),
         (0, 1, -1, NS, 4), (-1, 0, -1, EW, 4), (0, -1, -1, NS, 0), (1, 0, -1, EW, 0)],
}


def virtual_to_physical(ctx: Context, vch: int) -> int:
    """navigation.c's virtual2physical: the physical channel of ``vch`` given how ``ctx`` arrived."""
    sides = [[0, 1, 2, 3], [4, 5, 6, 7]]
    vc, pc = ctx.in_vch, ctx.in_pch
    change = (vc < 4 and pc > 3) or (vc > 3 and pc < 4)
    if change:
        (sides[0][0], sides[1][0]) = (sides[1][0], sides[0][0])
        (sides[0][1], sides[1][3]) = (sides[1][3], sides[0][1])
        (sides[0][2], sides[1][2]) = (sides[1][2], sides[0][2])
        (sides[0][3], sides[1][1]) = (sides[1][1], sides[0][3])
    side, local = (1, vc - 4) if vc > 3 else (0, vc)
    for _ in range(8):
        if sides[side][local] == pc:
            break
        for s in sides:
            if change:
                s[:] = s[1:] + s[:1]
            else:
                s[:] = s[3:] + s[:3]
    return sides[1][vch - 4] if vch > 3 else sides[0][vch]


class FirmwareRuntime(ModuleRuntime):
    """One module running the firmware's controller (``target.quirks.firmware_controller``)."""

    def __init__(self, hal: ModuleHal, role_table: RoleTable, *, module_id: int, seed: int = 0,
                 checksum: bool = False, target: Target = DEFAULT) -> None:
        super().__init__(hal, role_table, module_id=module_id, seed=seed, checksum=checksum, target=target)
        self.slots = [Stored(Context()) for _ in range(SLOTS)]
        self.use_flags = 0
        self.queue: list[FwTask | None] = [None] * QUEUE
        self.q_start = self.q_end = 0
        self.vectors = [NONE] * 8
        self.neighbour_cache = [0] * 8
        self.command_table = [NONE] * (MAX_ROLES * ROLE_COMMANDS)  # flat: [role][command]
        self.packet_id = 0
        self._load: list[bytes] = []
        self._entry = False
        self._wake = 0.0
        self._idle = False
        self._fired: int | None = None  # the event whose handler ran in the last scheduler step
        self._at: tuple[bytes | None, int | None] = (None, None)  # code and pc calling out, for observers
        self._main = self._activate()

    # ---- world interface -------------------------------------------------------------------
    def inject(self, fragment: bytes) -> None:
        """A fragment for the loader: this module becomes the entry module (``dcd_action``)."""
        if isinstance(fragment, int):
            self._error("inject: the fragment is not bytes")
            return
        self._entry = True
        if self.position is None:
            self._set_frame((0, 0, 0), NS, nav.IDENTITY)
        self._load.append(bytes(fragment))

    def receive(self, physical_channel: int, packet: bytes) -> None:
        if self.halted:
            return
        try:
            self._handle_message(bytes(packet), int(physical_channel))
        except Halt:
            pass
        except (TypeError, ValueError, OverflowError):
            self.bad_packets += 1
        except Exception as e:  # a VM bug must not crash the world: report it on this module
            self.halted = True
            self._error(f"internal error: {type(e).__name__}: {e}")

    def needs_step(self, events: bool = True) -> bool:
        """Idle (its main loop between steps with nothing queued) it only polls its sensors."""
        if self.halted:
            return False
        if not self._idle or self.q_start != self.q_end:
            return True
        return events and any(v != NONE and not v & DISABLED for v in self.vectors)

    def step(self) -> None:
        if self.halted or (self._wake != STEP and self.hal.now() < self._wake):
            return
        try:
            self._wake = next(self._main)
        except Halt:
            pass
        except StopIteration:
            self.halted = True
        except Exception as e:  # a VM bug must not crash the world: report it on this module
            self.halted = True
            self._error(f"internal error: {type(e).__name__}: {e}")

    # ---- main loop -------------------------------------------------------------------------
    def _activate(self) -> Generator[float, None, None]:
        yield STEP  # activate(): one simulator iteration before the role is read
        if self._entry:
            ctx = Context()
            while self._load:  # dcd_action
                code = self._load.pop(0)
                yield self.hal.now() + LOAD_DELAY_S - 1e-9
                for ch in range(8):
                    self._send_program(ctx, ch, code)
                ctx.program_id = (ctx.program_id + 1) & 0xFF
        while True:
            yield from self._scheduler_action()
            self._idle = True
            yield STEP
            self._idle = False

    def _scheduler_action(self) -> Generator[float, None, None]:
        yield from self._check_events()
        if self.q_end == self.q_start:
            return
        start = self.q_start
        task = self.queue[start]
        assert task is not None
        if not task.discard:
            if task.kind == TASK_INTERPRET:
                stored = self.slots[task.slot]
                again = yield from self._interpret(stored.context, stored.code, task.arg)
                if not again:
                    self.use_flags ^= 1 << task.slot
                else:
                    self._enqueue(FwTask(TASK_INTERPRET, slot=task.slot, arg=task.arg))
            else:
                ctx = Context(task.x, task.y, task.z, task.r, task.vch, task.pch)
                for ch in range(8):
                    if ch != task.vch:
                        self._send_command(ctx, ch, task.role, task.command, task.argument, task.packet_id)
                if self.roles.is_instance(self.role, task.role):
                    yield from self._execute_command(task.command, task.argument)
        self.q_start = (start + 1) % QUEUE

    def _check_events(self) -> Generator[float, None, None]:
        fired, self._fired = self._fired, None
        for vector in range(8):
            v = self.vectors[vector]
            if v != NONE and not v & DISABLED and self.hal.proximity(vector):
                if fired == vector:  # the same detection, one step later: counted, not logged
                    self.handler_refires += 1
                else:
                    self._log("handler", {"event": vector})
                self._fired = vector
                stored = self.slots[v % SLOTS]
                if self.observer is not None and fired != vector:
                    self.observer.handler_fired(self, vector, stored)  # type: ignore[arg-type]
                yield from self._interpret(stored.context, stored.code, 0)
                return

    # ---- packets ---------------------------------------------------------------------------
    def _handle_message(self, raw: bytes, ch: int) -> None:
        if len(raw) < 7 or not 0 <= ch <= 7:
            self.bad_packets += 1
            return
        kind, ident, x, y, z, r, vch = raw[0], raw[1], s8(raw[2]), s8(raw[3]), s8(raw[4]), raw[5], raw[6]
        if kind == 0:
            return
        if self.position is None and kind in (PROGRAM, COMMAND) and r in (NS, EW, UD) and vch < 8:
            self._set_frame((x, y, z), r, nav.virtual_to_physical(vch, ch))
        if kind == PROGRAM:
            slot = self._store(Context(x, y, z, r, vch, ch, ident), raw[7:])
            self._enqueue(FwTask(TASK_INTERPRET, slot=slot))
            self.programs_run += 1
            self._log("program", {"id": ident, "size": len(raw) - 7})
            if self.observer is not None:
                self.observer.program_stored(self, self.slots[slot])  # type: ignore[arg-type]
        elif kind == COMMAND and len(raw) >= 10:
            self._enqueue(FwTask(TASK_COMMAND, role=raw[7], command=raw[8], argument=raw[9], pch=ch,
                                 x=x, y=y, z=z, r=r, vch=vch, packet_id=ident))
        elif kind == NOTIFY and len(raw) >= 8:
            self.neighbour_cache[vch & 7] = raw[7]
            self.neighbour_roles[vch & 7] = raw[7]
        else:
            self._fail(3, kind)

    def _store(self, ctx: Context, code: bytes) -> int:
        for index in range(SLOTS):
            if not self.use_flags & 1 << index:
                self.use_flags |= 1 << index
                self.slots[index] = Stored(ctx, bytes(code))
                return index
        self._fail(1, 0)
        return 0

    def _save(self, ctx: Context, code: bytes) -> int:
        """save_program: a handler's or command's body, with its installer's context (not its id)."""
        for index in range(SLOTS):
            if not self.use_flags & 1 << index:
                self.use_flags |= 1 << index
                old = self.slots[index].context.program_id
                self.slots[index] = Stored(Context(ctx.x, ctx.y, ctx.z, ctx.r, ctx.in_vch, ctx.in_pch, old),
                                           bytes(code))
                return index
        self._fail(1, 1)
        return 0

    def _enqueue(self, task: FwTask) -> None:
        following = (self.q_end + 1) % QUEUE
        if following == self.q_start:
            self._fail(2, 0)
        self.queue[self.q_end] = task
        self.q_end = following

    def _header(self, ctx: Context, vch: int) -> tuple[int, tuple[int, int, int, int, int]] | None:
        """(physical channel, receiver x y z axis vch) for sending on virtual ``vch``; None when
        nobody is attached there."""
        if not (0 <= ctx.in_vch < 8 and 0 <= ctx.in_pch < 8):
            # a header with a channel past 7: the firmware reads outside its tables (undefined)
            self._fail(6, ctx.in_vch)
        pch = virtual_to_physical(ctx, vch)
        table = _RECEIVER.get(ctx.r)
        if table is None:
            self._fail(5, ctx.r)
            return None
        dx, dy, dz, axis, rvch = table[vch]
        if pch not in self.hal.connected_channels():
            return None
        return pch, (s8(ctx.x + dx), s8(ctx.y + dy), s8(ctx.z + dz), axis, rvch)

    def _transmit(self, pch: int, kind: int, ident: int, head: tuple[int, int, int, int, int],
                  body: bytes) -> None:
        x, y, z, axis, rvch = head
        self.link.sent += 1
        self.hal.send(pch, bytes((kind, ident & 0xFF, x & 0xFF, y & 0xFF, z & 0xFF, axis, rvch)) + body)

    def _send_program(self, ctx: Context, vch: int, code: bytes) -> None:
        found = self._header(ctx, vch)
        if found is not None:
            self._transmit(found[0], PROGRAM, ctx.program_id, found[1], code)

    def _send_command(self, ctx: Context, vch: int, role: int, command: int, arg: int,
                      ident: int | None) -> None:
        found = self._header(ctx, vch)
        if found is None:
            return
        if ident is None:
            ident, self.packet_id = self.packet_id, (self.packet_id + 1) & 0xFF
        self._transmit(found[0], COMMAND, ident, found[1], bytes((role & 0xFF, command & 0xFF, arg & 0xFF)))

    def _notify(self, ctx: Context, vch: int, role: int) -> None:
        found = self._header(ctx, vch)
        if found is None:
            return
        ident, self.packet_id = self.packet_id, (self.packet_id + 1) & 0xFF
        self._transmit(found[0], NOTIFY, ident, found[1], bytes((role & 0xFF,)))

    # ---- errors ----------------------------------------------------------------------------
    def _fail(self, number: int, argument: int, code: bytes | None = None, pc: int | None = None,
              what: str = "") -> None:
        """report_error: the module stops (dcdError.c). ``code``, ``pc``: the run that failed."""
        what = what or f"{ERRORS.get(number, 'error')} (error {number}.{argument})"
        message = f"{what}; module halted"
        if code is not None:  # a run's error, worded as the reports expect it
            message = f"program run: pc {pc}: {message}"
        self.halted = True
        if code is not None:
            self.run_errors.append(RunError(self.hal.now(), message, code, pc, True))
            del self.run_errors[:-MAX_LOG]
        self._error(message, code, pc)
        raise Halt(message)

    # ---- commands --------------------------------------------------------------------------
    def _execute_command(self, command: int, argument: int) -> Wait:
        argument &= 0xFF
        self._log("command", {"command": command, "arg": s8(argument)})
        if self.observer is not None:
            self.observer.command_executed(self, command, s8(argument), *self._at)
        hal = self.hal
        if command == 1:
            hal.rotate_continuously(argument)
        elif command == 2:
            hal.rotate_continuously(-argument)
        elif command == 3:
            hal.stop_joint()
        elif command == 4:
            hal.rotate_by(10.0 * s8(argument))
        elif command == 5:
            hal.rotate_to(10.0 * s8(argument))
        elif 128 <= command < 128 + ROLE_COMMANDS:
            index = self.command_table[(self.role % 256) * ROLE_COMMANDS + command - 128] \
                if self.role < MAX_ROLES else NONE
            if index != NONE:
                stored = self.slots[index % SLOTS]
                again = yield from self._interpret(stored.context, stored.code, argument)
                if again:
                    self._enqueue(FwTask(TASK_INTERPRET, slot=index % SLOTS, arg=argument))
        return 0

    def _send_command_all(self, ctx: Context, role: int, command: int, argument: int) -> Wait:
        if self.observer is not None:
            self.observer.command_sent(self, role, command, s8(argument), *self._at)
        for ch in range(8):
            self._send_command(ctx, ch, role, command, argument, None)
        if self.roles.is_instance(self.role, role):
            yield from self._execute_command(command, argument)
        return 0

    # ---- the interpreter (dcdInterpreter.c) ------------------------------------------------
    def _interpret(self, ctx: Context, code: bytes, argument: int) -> Wait:  # noqa: C901 - one dispatch
        self.runs += 1
        stack: list[int] = []
        pc, count, size, at = 0, 0, len(code), 0

        def push(value: int) -> None:
            if len(stack) == MAX_STACK:
                self._fail(7, MAX_STACK, code, at)
            stack.append(s8(value))

        def pop() -> int:
            if not stack:  # the firmware reads below its stack; compiled code never does
                self._fail(8, 0, code, at, "stack underflow")
            return stack.pop()

        def operand(k: int) -> int:
            return code[pc + k] if pc + k < size else 0

        connected = self.hal.connected_channels
        while pc < size:
            if count > MAX_INSTRUCTIONS:
                self._fail(11, pc, code, pc, f"more than {MAX_INSTRUCTIONS} instructions in one run")
            count += 1
            at = pc
            op = code[pc]
            pc += 1
            if op in (1, 2, 3):
                push(int(ctx.r == (EW, NS, UD)[op - 1]))
            elif op == 4:  # CONNECTED: bit c+1 for physical channel c (channel 7 lost)
                push(sum(1 << c for c in connected() if 0 <= c <= 7) << 1 & 0xFF)
            elif op == 5:
                push(sum(1 for c in connected() if 0 <= c <= 7))
            elif op == 49:
                push((pop() & 0xFF).bit_count())
            elif op == 22:
                tos = pop()
                push(int(pop() > tos))
            elif op == 6:
                push(int(pop() == 0))
            elif op == 7:
                push(int(pop() == 1))
            elif op == 12:
                push(self._connected_dir(ctx, operand(0), code, at).bit_count())
                pc += 1
            elif op == 36:
                push(self._neighbour_down(ctx, operand(0), code, at))
                pc += 1
            elif op == 34:
                push(int(self.roles.is_instance(self.role, operand(0))))
                pc += 1
            elif op == 13:
                return 0
            elif op == 14:
                return 1
            elif op in (15, 47):
                if (pop() != 0) == (op == 47):
                    pc = operand(0)
                else:
                    pc += 1
            elif op == 16:
                pc = operand(0)
            elif op == 17:
                self._at = (code, at)
                self._set_role(ctx, operand(0))
                pc += 1
            elif op == 18:
                for ch in range(8):
                    if ch != ctx.in_vch:
                        self._send_program(ctx, ch, code)
                return 0
            elif op == 33:
                command, arg = operand(0), operand(1)
                pc += 2
                self._at = (code, at)
                yield from self._execute_command(command, arg)
            elif op == 127 or op == 51:
                pass
            elif op in (24, 25, 26, 27):
                coord = ctx.y if op in (26, 27) else ctx.x
                value = pop()
                push(int(coord > value) if op in (24, 26) else int(coord < value))
            elif op == 30:
                vector, adr, n = operand(0), operand(1), operand(2)
                pc += 3
                self.vectors[vector & 7] = index = self._save(ctx, code[adr:adr + n])
                if self.observer is not None:
                    self.observer.handler_installed(self, vector, self.slots[index], code, at)  # type: ignore[arg-type]
            elif op == 42:
                role, raw, adr, n = operand(0), operand(1), operand(2), operand(3)
                pc += 4
                self._at = (code, at)
                self._install_command(ctx, code[adr:adr + n], role, raw)
            elif op == 32:
                vector = operand(0) & 7
                pc += 1
                self.vectors[vector] = NONE
                self.use_flags ^= 1 << vector  # the firmware frees the slot numbered like the event
            elif op == 44:
                vector = operand(0) & 7
                pc += 1
                if self.vectors[vector] != NONE:
                    self.vectors[vector] |= DISABLED
            elif op == 45:
                vector = operand(0) & 7
                pc += 1
                if self.vectors[vector] != NONE:
                    self.vectors[vector] ^= DISABLED  # toggles
            elif op == 31:
                role, command, arg = operand(0), operand(1), operand(2)
                pc += 3
                self._at = (code, at)
                yield from self._send_command_all(ctx, role, command, arg)
            elif op == 43:
                yield self.hal.now() + SLEEP_S - 1e-9
            elif op == 48:
                turns = operand(0)
                pc += 1
                yield from self._sleep_rotations(turns)
            elif op == 46:
                command = operand(0)
                pc += 1
                i = self.q_start
                while i != self.q_end:
                    task = self.queue[i]
                    if task is not None and task.kind == TASK_COMMAND and task.command == command:
                        task.discard = True
                    i = (i + 1) % QUEUE
            elif op == 52:
                function, arg = pop() & 0xFF, pop() & 0xFF
                self._at = (code, at)
                if function < 64 or function >= 128:
                    yield from self._execute_command(function, arg)
                elif function == 64:
                    yield from self._send_command_all(ctx, ANY_ROLE, arg, 0)
                else:
                    self._fail(19, function, code, at)
                push(0)
            elif op == 53:
                if operand(0) != 0:
                    self._fail(21, operand(0), code, at)
                push(argument)
                pc += 1
            elif op == 54:
                push(operand(0))
                pc += 1
            elif op == 55:
                self.set_led(operand(0))
                pc += 1
            elif op > 127:
                push(op ^ 128)
            else:
                ins = BY_OPCODE.get(op)
                self._fail(9, at, code, at, f"unknown instruction {op}" + (f" ({ins.name})" if ins else ""))
        return 0

    def _set_role(self, ctx: Context, role: int) -> None:
        if role != self.role:
            self.role_history.append((self.hal.now(), role))
            self._log("role", {"role": role, "name": self.roles.name(role)})
            if self.observer is not None:
                self.observer.role_set(self, role, *self._at)
        self.role = role
        for ch in range(8):
            self._notify(ctx, ch, role)

    def _install_command(self, ctx: Context, code: bytes, role: int, raw: int) -> None:
        index = self._save(ctx, code)
        if raw < 128:
            self._fail(18, 0)  # the firmware passes an uninitialised value here
        command = raw - 128
        if (role > MAX_ROLES and role != ANY_ROLE) or command > ROLE_COMMANDS:
            self._fail(18, (role << 4) + command & 0xFF)
        table = self.command_table  # command 5 writes into the next role's row, as in the firmware
        if role == ANY_ROLE:
            table[command] = index
        for r in range(1, MAX_ROLES):
            if self.roles.is_instance(r, role) and r * ROLE_COMMANDS + command < len(table):
                table[r * ROLE_COMMANDS + command] = index
        if self.observer is not None:
            self.observer.command_installed(self, role, raw, self.slots[index], *self._at)  # type: ignore[arg-type]

    def _connected_dir(self, ctx: Context, direction: int, code: bytes, at: int) -> int:
        """deprecated_compute_connected_dir: counts for the few axis/direction pairs it knows."""
        connected = self.hal.connected_channels()

        def count(*vchs: int) -> int:
            return sum(1 for v in vchs if virtual_to_physical(ctx, v) in connected)

        if ctx.r == NS:
            if direction == NORTH:
                return count(0, 1, 2, 3)
            if direction == DOWN:
                return count(2, 6)
            self._fail(12, direction, code, at)
        if ctx.r == EW:
            pairs = {UP: (0, 4), EAST: (0, 1, 2, 3), WEST: (4, 5, 6, 7), DOWN: (2, 6), NORTH: (1, 5)}
            if direction in pairs:
                return count(*pairs[direction])
            self._fail(12, direction, code, at)
        self._fail(13, ctx.r, code, at)
        return 0

    def _neighbour_down(self, ctx: Context, role: int, code: bytes, at: int) -> int:
        """check_neighbor_role(DOWN): the notified roles of the virtual channels below."""
        cache = self.neighbour_cache
        if ctx.r in (NS, EW):
            return int(self.roles.is_instance(cache[2], role) or self.roles.is_instance(cache[6], role))
        if ctx.r == UD:
            return int(any(self.roles.is_instance(cache[c], role) for c in range(4, 8)))
        self._fail(13, ctx.r, code, at)
        return 0

    def _sleep_rotations(self, rotations: int) -> Generator[float, None, None]:
        """Counts the joint's returns to the quarter it started in (getJointPosition: 0..3)."""
        seen, start, at_start = 0, joint_quarter(self.hal.joint_angle_deg()), True
        while seen < rotations:
            now = joint_quarter(self.hal.joint_angle_deg())
            if at_start:
                at_start = now == start
            elif now == start:
                at_start = True
                seen += 1
            yield STEP


def joint_quarter(angle_deg: float) -> int:
    """The ATRON API's getJointPosition: which quarter of a turn the joint is nearest."""
    enc = (angle_deg % 360.0) / 360.0
    if enc <= 0.125 or abs(enc - 1.0) < 0.125:
        return 0
    for quarter in (1, 2, 3):
        if abs(enc - quarter / 4) <= 0.125:
            return quarter
    return 0


def make_runtime(hal: ModuleHal, role_table: RoleTable, *, module_id: int, seed: int = 0,
                 target: Target = DEFAULT) -> ModuleRuntime:
    """The runtime a world gives a module under ``target`` (the firmware's own controller when the
    target's quirks say so)."""
    cls = FirmwareRuntime if target.quirks.firmware_controller else ModuleRuntime
    return cls(hal, role_table, module_id=module_id, seed=seed, target=target)
