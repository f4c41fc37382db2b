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

The interpreter and the commands it executes are in ``vm.firmware_interpreter``, the firmware's
tables in ``vm.firmware_parts``. The blocking parts are Python generators: ``yield STEP`` waits
for the next scheduler step, ``yield t`` for the first step at or after time ``t``.
``vm.runtime.ModuleRuntime`` supplies the world interface, the logs and reports this class fills in.
"""

from __future__ import annotations

from collections.abc import Generator

from vm import navigation as nav
from vm.firmware_interpreter import FirmwareInterpreter
from vm.firmware_parts import (
    DISABLED,
    ERRORS,
    EW,
    LOAD_DELAY_S,
    MAX_ROLES,
    NONE,
    NS,
    QUEUE,
    RECEIVER,
    ROLE_COMMANDS,
    SLOTS,
    STEP,
    TASK_COMMAND,
    TASK_INTERPRET,
    UD,
    Context,
    FwTask,
    Halt,
    Stored,
    joint_quarter,
    s8,
    virtual_to_physical,
)
from vm.hal import ModuleHal
from vm.isa.targets import DEFAULT, Target
from vm.packets import COMMAND, NOTIFY, PROGRAM
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime, RunError
from vm.runtime_node import MAX_LOG

__all__ = ["Context", "FirmwareRuntime", "joint_quarter", "make_runtime", "virtual_to_physical"]


class FirmwareRuntime(FirmwareInterpreter, ModuleRuntime):
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
        table = RECEIVER.get(ctx.r)
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


def make_runtime(hal: ModuleHal, role_table: RoleTable, *, module_id: int, seed: int = 0,
                 target: Target = DEFAULT) -> ModuleRuntime:
    """The runtime a world gives a module under ``target`` (the firmware's own controller when the
    target's quirks say so)."""
    cls = FirmwareRuntime if target.quirks.firmware_controller else ModuleRuntime
    return cls(hal, role_table, module_id=module_id, seed=seed, target=target)
