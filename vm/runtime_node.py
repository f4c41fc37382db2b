"""A DCD-VM module as a node of the structure's network: its frame, packets in and out,
at-most-once acceptance, and its error and event log. ``vm.runtime.ModuleRuntime`` adds the
scheduler and what programs call.

Fault tolerance (docs/vm.md), in two parts:
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

The firmware profile (``target`` with vm.isa.targets quirks, docs/vm.md) has neither: packets
are sent once and never acknowledged, every program and command packet that arrives is run or
forwarded again (so they circulate in cyclic structures until a store or queue overflows), a
halted module hears nothing, and receivers' coordinates are computed with the UD 5/7 x-offsets
swapped. Its receipt check is structural only (``verify`` without a target), so an opcode the
firmware lacks reaches the interpreter and halts the module as on the robot.
"""

from __future__ import annotations

import random
from collections import deque
from collections.abc import Callable

from vm import navigation as nav
from vm.hal import ModuleHal
from vm.interpreter import Frame
from vm.isa.opcodes import PUBLISHED_SLOTS, STATE_SLOTS, USER_COMMAND_BASE, carried_data_offset
from vm.isa.targets import DEFAULT, Target
from vm.isa.verifier import verify
from vm.observer import RuntimeObserver
from vm.packets import (
    COMMAND,
    PROGRAM,
    AckPacket,
    CommandPacket,
    NotifyPacket,
    PacketError,
    ProgramPacket,
    ValuePacket,
    decode,
    header_bytes,
    make_header,
    unseal,
)
from vm.roles import RoleTable
from vm.runtime_hold import HOLD_S, MAX_HELD, Held, HeldCommands
from vm.runtime_link import Link
from vm.runtime_store import PROGRAM as PROGRAM_SLOT
from vm.runtime_store import Slot, Store, StoreFull, Task

COMMAND_MEMORY = 30.0  # seconds a seen command packet is remembered
MAX_INBOX = 64
MAX_LOG = 10_000
EventHook = Callable[[str, dict[str, object]], None]


def program_key(code: bytes) -> bytes:
    """What identifies a program besides its id: its code without the value it carries (which
    changes from module to module)."""
    at = carried_data_offset(code)
    return code if at is None else code[:at]


class ModuleNode:
    def __init__(self, hal: ModuleHal, role_table: RoleTable, *, module_id: int, seed: int = 0,
                 checksum: bool = False, target: Target = DEFAULT) -> None:
        self.hal = hal
        self.target = target
        self.halted = False  # firmware profile: an unknown instruction stopped this module
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
        self.event_log: list[tuple[float, str, dict[str, object]]] = []
        self.on_event: EventHook | None = None
        self.observer: RuntimeObserver | None = None  # vm.observer: off by default
        self._running: Frame | None = None  # the frame of the run in progress, kept only when observed
        self.neighbour_roles = [0] * 8  # by virtual channel
        # State (this project's extension): the module's state memory, the last value of each
        # published state that each neighbour sent (by virtual channel), which neighbours named
        # this module their parent, and this module's parent: the physical channel on which the
        # first program it accepted arrived (None on the entry module, where programs are injected).
        self.state = [0] * STATE_SLOTS
        self.neighbour_cache: list[list[int | None]] = [[None] * PUBLISHED_SLOTS for _ in range(8)]
        self.neighbour_is_child = [False] * 8
        self.parent_channel: int | None = None
        self.origin = False  # programs are injected here: the origin of the coordinates
        self._keeps_values = False  # a value packet has arrived (lost neighbours are then watched)
        self._value_seq: dict[tuple[int, int], int] = {}  # (physical channel, state) → last id
        self.store = Store(capacity=target.program_slots, slot_bytes=target.slot_bytes)
        self.link = Link(hal, self.rng, checksum=checksum, acknowledged=not target.quirks.no_acknowledgements)
        self.bad_packets = 0
        self.duplicates = 0
        self._inbox: deque[tuple[int, bytes]] = deque()
        self._seen_programs: set[tuple[int, bytes]] = set()
        self._seen_commands: dict[tuple[int, int, int, int], float] = {}
        self._notify_seq: dict[int, int] = {}  # physical channel → last notify id
        self._reported: set[object] = set()
        self._next_inject_id = 1
        self._arrivals = 0  # programs accepted
        self._next_local_id = self.rng.randrange(256)
        # commands that came before their code or the module's role (vm.runtime_hold); the
        # firmware drops them, this project's VM holds them
        self.held = HeldCommands()
        self._holds = not target.quirks.firmware_controller

    # ---- world interface -------------------------------------------------------------------
    def receive(self, physical_channel: int, packet: bytes) -> None:
        if self.halted:
            return
        if len(self._inbox) >= MAX_INBOX:
            self._error("receive buffer full, packet dropped")
            return
        try:
            if isinstance(packet, int):  # bytes(n) would make n zero bytes
                raise TypeError("a packet is bytes")
            self._inbox.append((int(physical_channel), bytes(packet)))
        except (TypeError, ValueError, OverflowError):
            self.bad_packets += 1

    def inject(self, fragment: bytes) -> None:
        """Enter a fragment here; the first injection defines the frame (origin, NS, identity)."""
        if self.position is None:
            self._set_frame((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY)
        self.origin = True
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

    def hold_frame(self, position: tuple[int, int, int], axis: int, mapping: tuple[int, ...]) -> None:
        """Start with this frame (coordinates, axis, virtual-to-physical map) as if learned in an
        earlier run: a robot that ran a sequence forward and now runs it backwards
        (docs/reconfiguration.md "Backwards"). Before anything arrives; a bad frame is refused."""
        if (len(position) != 3 or axis not in (nav.NORTH_SOUTH, nav.EAST_WEST, nav.UP_DOWN)
                or nav.axis_for_position(*position) != axis or sorted(mapping) != list(range(8))):
            raise ValueError(f"module {self.module_id}: not a frame: {position}, axis {axis}, {mapping}")
        self._set_frame(tuple(position), axis, tuple(mapping))  # type: ignore[arg-type]

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
        if self.position is None or self._teaches(ch):
            self._set_frame((h.x, h.y, h.z), h.r, nav.virtual_to_physical(h.vch, ch))
            self._frame_learned(ch)
        if isinstance(p, ProgramPacket):
            if self._accept_program(p.code, h.id, ch, h.vch):
                self.link.send_ack(ch, raw)
        elif isinstance(p, CommandPacket):
            self.link.send_ack(ch, raw)
            self._accept_command(p, ch)
        elif isinstance(p, NotifyPacket):
            self.link.send_ack(ch, raw)
            self._accept_notify(p, ch)
        elif isinstance(p, ValuePacket):
            self.link.send_ack(ch, raw)
            self._accept_value(p, ch)

    def _accept_program(self, code: bytes, ident: int, ch: int | None, vch: int | None) -> bool:
        """Store and queue a program; False when it should be offered again later (no room)."""
        key = (ident, program_key(code))
        if key in self._seen_programs and not self.target.quirks.no_duplicate_suppression:
            self.duplicates += 1
            return True
        problems = verify(code)
        if problems:
            self._seen_programs.add(key)
            self._error(f"program {ident} rejected: {'; '.join(problems)}")
            return True
        ctx = (*self.position, self.axis, vch) if self.position and self.axis else None
        try:
            slot = self.store.add_and_queue(Slot(code, ident, PROGRAM_SLOT, ch, ctx))
        except StoreFull as e:
            self._error_once(("full", key), f"program {ident} not accepted: {e}")
            return False
        self._seen_programs.add(key)
        slot.arrival, self._arrivals = self._arrivals, self._arrivals + 1
        if self.parent_channel is None and ch is not None:  # the tree: who first brought a program
            self.parent_channel = ch
        self._log("program", {"id": ident, "size": len(code)})
        if self.observer is not None:
            self.observer.program_stored(self, slot)
        return True

    def _accept_command(self, p: CommandPacket, ch: int) -> None:
        key = (p.header.id, p.role, p.command, p.argument & 0xFF)
        if key in self._seen_commands and not self.target.quirks.no_duplicate_suppression:
            self.duplicates += 1
            return
        self._seen_commands[key] = self.hal.now()
        self._flood_command(p.header.id, p.role, p.command, p.argument, exclude=ch)
        if self.roles.is_instance(self.role, p.role):
            self._queue_command(p.command, p.argument)
        elif self.role == 0 and self._holds and p.command >= USER_COMMAND_BASE:
            self._hold(p.role, p.command, p.argument)  # the module may take the role yet

    def _hold(self, role: int, command: int, arg: int) -> None:
        if self.held.hold(self.hal.now(), role, command, arg):
            self._log("command_held", {"command": command, "arg": arg})
        else:
            self._error(f"user command {command - USER_COMMAND_BASE} (argument {arg}) not run: "
                        f"{MAX_HELD} commands wait for their code already")

    def _release_held(self) -> None:
        """Queue the held commands whose code is installed for the module's role now."""
        if not self.held:
            return

        def ready(held: Held) -> bool | None:
            if self.role == 0:
                return False
            if not self.roles.is_instance(self.role, held.role):
                return None  # not for this module
            return self.store.command_slot(self.role, held.command - USER_COMMAND_BASE) is not None

        for held in self.held.take(ready):
            self._queue_command(held.command, held.arg)

    def _expire_held(self) -> None:
        if not self.held:
            return
        for held in self.held.expire(self.hal.now()):
            if self.role != 0 and self.roles.is_instance(self.role, held.role):
                self._error(f"user command {held.command - USER_COMMAND_BASE} (argument {held.arg}) "
                            f"dropped: its code did not arrive within {HOLD_S:g} s")

    def _accept_notify(self, p: NotifyPacket, ch: int) -> None:
        last = self._notify_seq.get(ch)
        if last is not None and not 0 < (p.header.id - last) & 0xFF < 128:
            return  # a duplicate or an older notify
        self._notify_seq[ch] = p.header.id
        v = self._p2v[ch]
        if self.neighbour_roles[v] != p.role:
            self.neighbour_roles[v] = p.role
            self._values_changed()
            self._neighbour_role_changed()

    def _accept_value(self, p: ValuePacket, ch: int) -> None:
        key = (ch, p.index)
        last = self._value_seq.get(key)
        if last is not None and not 0 < (p.header.id - last) & 0xFF < 128:
            return  # a duplicate or an older value
        self._value_seq[key] = p.header.id
        self._keeps_values = True
        v = self._p2v[ch]
        changed = self.neighbour_cache[v][p.index] != p.value or self.neighbour_is_child[v] != p.to_parent
        self.neighbour_cache[v][p.index] = p.value
        self.neighbour_is_child[v] = p.to_parent
        if changed:
            self._values_changed()

    def _values_changed(self) -> None:
        """A state or a neighbour's value changed: programs waiting in END_WAIT run again."""

    def _neighbour_role_changed(self) -> None:
        """A neighbour announced another role (``vm.runtime_shape`` checks roles that read it)."""

    def _frame_learned(self, ch: int) -> None:
        """A packet on ``ch`` gave the module its coordinates (``vm.runtime_shape``)."""

    def _teaches(self, ch: int) -> bool:
        """Whether a packet arriving on ``ch`` gives a module that has a frame a new one."""
        return False

    # ---- sending ---------------------------------------------------------------------------
    def _send_all(self, type_: int, ident: int, body: bytes, exclude: int | None) -> None:
        if self.position is None or self.axis is None:
            return
        x, y, z = self.position
        for ch in sorted(self.hal.connected_channels()):
            if ch == exclude or not 0 <= ch <= 7:
                continue
            rx, ry, rz, raxis, rvch = nav.receiver(x, y, z, self.axis, self._p2v[ch],
                                                   ud_offsets_swapped=self.target.quirks.ud_offsets_swapped)
            self.link.send(ch, header_bytes(make_header(type_, ident, rx, ry, rz, raxis, rvch)) + body)

    def _migrate(self, slot: Slot) -> None:
        ident = slot.ident
        if slot.kind != PROGRAM_SLOT:  # a handler or command spreading: a new program each time
            ident = self._local_id()
            self._seen_programs.add((ident, program_key(slot.code)))
        self._send_all(PROGRAM, ident, slot.code, exclude=slot.in_physical)

    def _flood_command(self, ident: int, role: int, command: int, arg: int, exclude: int | None) -> None:
        self._send_all(COMMAND, ident, bytes((role & 0xFF, command & 0xFF, arg & 0xFF)), exclude)

    # ---- helpers ---------------------------------------------------------------------------
    def _queue_command(self, command: int, arg: int) -> None:
        try:
            self.store.queue(Task(None, arg=arg, command=command))
        except StoreFull as e:
            self._error(f"command {command} not run: {e}")

    def _local_id(self) -> int:
        self._next_local_id = (self._next_local_id + 1) & 0xFF
        return self._next_local_id

    def _set_frame(self, position: tuple[int, int, int], axis: int, mapping: tuple[int, ...]) -> None:
        self.position, self.axis, self.mapping = position, axis, mapping
        self._p2v = nav.invert(mapping)

    def _expire_commands(self) -> None:
        self._expire_held()
        now = self.hal.now()
        if self._seen_commands:
            self._seen_commands = {k: t for k, t in self._seen_commands.items() if now - t < COMMAND_MEMORY}

    def _error(self, message: str, code: bytes | None = None, pc: int | None = None) -> None:
        """``code``, ``pc``: where a run failed, for the observer (default: the instruction running)."""
        self.errors.append((self.hal.now(), message))
        del self.errors[:-MAX_LOG]
        self._log("error", {"message": message})
        if self.observer is not None:
            if code is None:
                code, pc = self._where()
            self.observer.error(self, message, code, pc)

    def _where(self) -> tuple[bytes | None, int | None]:
        """The code running now and the offset of the instruction calling the module (observed runs)."""
        frame = self._running
        return (frame.code, frame.at) if frame is not None else (None, None)

    def _error_once(self, key: object, message: str) -> None:
        if key not in self._reported:
            self._reported.add(key)
            self._error(message)

    def _log(self, kind: str, detail: dict[str, object]) -> None:
        self.event_log.append((self.hal.now(), kind, detail))
        del self.event_log[:-MAX_LOG]
        if self.on_event is not None:
            self.on_event(kind, detail)
