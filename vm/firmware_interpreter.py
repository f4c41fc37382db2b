"""The ATRON firmware's interpreter (dcdInterpreter.c) and the commands it executes, as a part of
``vm.runtime_firmware.FirmwareRuntime``: a run is a generator that yields while it blocks (SLEEP,
SLEEP_ROTATIONS, and the handlers and user commands it runs inline)."""

from __future__ import annotations

from collections.abc import Generator
from typing import TYPE_CHECKING

from vm.firmware_parts import (
    DISABLED,
    DOWN,
    EAST,
    EW,
    MAX_INSTRUCTIONS,
    MAX_ROLES,
    MAX_STACK,
    NONE,
    NORTH,
    NS,
    QUEUE,
    ROLE_COMMANDS,
    SLEEP_S,
    SLOTS,
    STEP,
    TASK_COMMAND,
    TASK_INTERPRET,
    UD,
    UP,
    WEST,
    Context,
    FwTask,
    Wait,
    joint_quarter,
    s8,
    virtual_to_physical,
)
from vm.interpreter import Frame
from vm.isa.opcodes import BY_OPCODE
from vm.roles import ANY_ROLE

if TYPE_CHECKING:
    from vm.runtime_firmware import FirmwareRuntime


class FirmwareInterpreter:
    """The interpreter's half of ``FirmwareRuntime`` (the methods use its store, queue and links)."""

    def _execute_command(self: FirmwareRuntime, command: int, argument: int) -> Wait:
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

    def _send_command_all(self: FirmwareRuntime, ctx: Context, role: int, command: int,
                          argument: int) -> Wait:
        if self.observer is not None:
            self.observer.command_sent(self, role, command, s8(argument), *self._at)
        for ch in range(8):
            self._send_command(ctx, ch, role, command, argument, None)
        if self.roles.is_instance(self.role, role):
            yield from self._execute_command(command, argument)
        return 0

    # ---- the interpreter (dcdInterpreter.c) ------------------------------------------------
    def _interpret(self: FirmwareRuntime, ctx: Context, code: bytes, argument: int) -> Wait:  # noqa: C901 - one dispatch
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
        observer = self.observer
        watch = observer.before_instruction if observer is not None and observer.instructions else None
        frame = Frame(code, argument) if watch is not None else None
        while pc < size:
            if count > MAX_INSTRUCTIONS:
                self._fail(11, pc, code, pc, f"more than {MAX_INSTRUCTIONS} instructions in one run")
            count += 1
            at = pc
            if frame is not None:  # observed (a debugger): the instruction about to run, as a frame
                frame.pc, frame.stack = pc, list(stack)
                watch(self, frame)  # type: ignore[misc, arg-type]
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
                    stored = self.slots[index]
                    self.observer.handler_installed(self, vector, stored, code, at)  # type: ignore[arg-type]
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

    def _set_role(self: FirmwareRuntime, ctx: Context, role: int) -> None:
        if role != self.role:
            self.role_history.append((self.hal.now(), role))
            self._log("role", {"role": role, "name": self.roles.name(role)})
            if self.observer is not None:
                self.observer.role_set(self, role, *self._at)
        self.role = role
        for ch in range(8):
            self._notify(ctx, ch, role)

    def _install_command(self: FirmwareRuntime, ctx: Context, code: bytes, role: int, raw: int) -> None:
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

    def _connected_dir(self: FirmwareRuntime, ctx: Context, direction: int, code: bytes, at: int) -> int:
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

    def _neighbour_down(self: FirmwareRuntime, ctx: Context, role: int, code: bytes, at: int) -> int:
        """check_neighbor_role(DOWN): the notified roles of the virtual channels below."""
        cache = self.neighbour_cache
        if ctx.r in (NS, EW):
            return int(self.roles.is_instance(cache[2], role) or self.roles.is_instance(cache[6], role))
        if ctx.r == UD:
            return int(any(self.roles.is_instance(cache[c], role) for c in range(4, 8)))
        self._fail(13, ctx.r, code, at)
        return 0

    def _sleep_rotations(self: FirmwareRuntime, rotations: int) -> Generator[float, None, None]:
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
