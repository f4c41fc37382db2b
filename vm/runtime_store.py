"""Per-module storage of the DCD-VM with the hardware limits of docs/vm.md: program slots,
task queue entries, event vectors and the command table. Running out is reported by the caller
as a runtime error (``StoreFull``), never a crash.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vm.interpreter import Frame
from vm.isa.opcodes import PROGRAM_SLOTS, SLOT_BYTES, USER_COMMANDS

SLOTS = PROGRAM_SLOTS
QUEUE = 10
VECTORS = 8
PROGRAM, HANDLER, USER_COMMAND, LOCAL = "program", "handler", "command", "local"
RERUN = "rediscovery"  # a kept program run again after a connection change (vm.runtime_shape)


class StoreFull(Exception):
    pass


@dataclass(eq=False)
class Slot:
    code: bytes
    ident: int  # program id (the packet id it travels with)
    kind: str  # PROGRAM (received or injected), HANDLER or USER_COMMAND
    in_physical: int | None = None  # channel it came in on (None: injected or installed here)
    context: tuple[int, int, int, int, int | None] | None = None  # x, y, z, r, incoming virtual
    refs: int = 0  # command-table entries pointing here
    started: bool = False  # has run at least once
    role: int = 0  # a handler: the role the module played when it installed it (vm.runtime_shape)
    arrival: int = 0  # a program: how many programs the module accepted before it


@dataclass(eq=False)
class Task:
    slot: Slot | None  # program to run, or None for a command task
    arg: int = 0
    command: int | None = None  # the command this task runs (for CLEAR_COMMAND_QUEUE)
    frame: Frame | None = None  # None until started; kept while suspended
    wake_time: float | None = None
    wake_turns: float | None = None
    waiting: bool = False  # END_WAIT: until a value of the module changes
    wake_action: bool = False  # Outcome.ACTION: until the world answers the connector/joint action


@dataclass
class Vector:
    slot: Slot
    enabled: bool = True
    armed: bool = True  # cleared when it fires, set again when the sensor clears or on enable


@dataclass
class Store:
    slots: list[Slot] = field(default_factory=list)
    tasks: list[Task] = field(default_factory=list)
    vectors: list[Vector | None] = field(default_factory=lambda: [None] * VECTORS)
    commands: dict[int, list[Slot | None]] = field(default_factory=dict)
    capacity: int = SLOTS  # program slots (the target's, vm.isa.targets)
    slot_bytes: int = SLOT_BYTES

    def add_slot(self, slot: Slot) -> Slot:
        if len(slot.code) > self.slot_bytes:
            raise StoreFull(f"program of {len(slot.code)} bytes exceeds the {self.slot_bytes}-byte slot")
        if len(self.slots) >= self.capacity:
            raise StoreFull(f"all {self.capacity} program slots are in use")
        self.slots.append(slot)
        return slot

    def free_slot(self, slot: Slot | None) -> None:
        if slot is not None and any(s is slot for s in self.slots):
            self.slots = [s for s in self.slots if s is not slot]

    def add_and_queue(self, slot: Slot) -> Slot:
        """Store ``slot`` and queue a run of it, or neither (StoreFull)."""
        self.add_slot(slot)
        try:
            self.queue(Task(slot))
        except StoreFull:
            self.free_slot(slot)
            raise
        return slot

    def queue(self, task: Task) -> None:
        if len(self.tasks) >= QUEUE:
            raise StoreFull(f"task queue full ({QUEUE} entries)")
        self.tasks.append(task)

    def set_vector(self, event: int, slot: Slot) -> None:
        self.clear_vector(event)
        self.vectors[event] = Vector(slot)

    def clear_vector(self, event: int) -> None:
        old = self.vectors[event]
        self.vectors[event] = None
        if old is not None and not self._slot_in_use(old.slot):
            self.free_slot(old.slot)

    def set_command(self, role: int, k: int, slot: Slot) -> None:
        entries = self.commands.setdefault(role, [None] * USER_COMMANDS)
        old = entries[k]
        entries[k] = slot
        slot.refs += 1
        if old is not None:
            old.refs -= 1
            if old.refs <= 0 and not self._slot_in_use(old):
                self.free_slot(old)

    def command_slot(self, role: int, k: int) -> Slot | None:
        entries = self.commands.get(role)
        return entries[k] if entries and 0 <= k < USER_COMMANDS else None

    def release_after_run(self, slot: Slot | None) -> None:
        """A run of ``slot`` ended for good: free it unless something still needs it."""
        if slot is None or self._slot_in_use(slot):
            return
        if slot.kind in (PROGRAM, LOCAL, RERUN):
            self.free_slot(slot)
        elif slot.kind == HANDLER and not any(v is not None and v.slot is slot for v in self.vectors):
            self.free_slot(slot)
        elif slot.kind == USER_COMMAND and slot.refs <= 0:
            self.free_slot(slot)

    def _slot_in_use(self, slot: Slot) -> bool:
        return any(t.slot is slot for t in self.tasks)
