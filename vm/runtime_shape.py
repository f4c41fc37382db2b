"""Roles that follow the shape (docs/vm.md, "When discovery runs"): what a module of this
project's VM does when its connections change (``hal.connected_channels()``), whether by its own
action, a neighbour's or from outside.

- It keeps a copy of every program it accepted once the program's first run has ended (``kept``,
  in arrival order, at most ``KEPT_PROGRAMS``), and offers them on every connector that becomes
  attached: a module that
  arrives without a program receives them as over the first diffusion (acknowledged, retransmitted,
  and run once: a module that already has them acknowledges the copies and runs nothing).
- It tells a new neighbour its role (a notify on the new connector) and forgets the role and
  values of a neighbour that left.
- It checks its roles again with the one meaning of discovery: the first deployed role whose
  invariants hold. Programs that wait for a change of value (``END_WAIT``, the discovery of roles
  that read state) are woken. The programs that take a role (``SET_ROLE_NOTIFY`` outside a stored
  body: the discovery fragments) are run again, one after another in arrival order, as a *round*
  that migrates nowhere: inside it ``HAS_ROLE`` answers for the role taken in the round so far
  (none at its start), so the guards the compiler puts in later fragments let the first holding
  role win. A round that finds the role the module already plays stops that run (nothing to do);
  one that finds another role ends what the module runs for its old role (its behaviours and
  command runs, its event handlers, its joint's motion unless a quarter turn is under way) and
  then, after the fragment that took the new role, runs the programs that test a role (the
  continuation fragments with the rest of the role's entry code); a round in which no role holds
  leaves the module without a role, ended the same way. The same round runs when a
  neighbour announces another role and the discovery fragments read neighbour roles, once no
  program's first run is going on at the module.
- Coordinates: a module whose connections have all changed at once (it left the part it was
  attached to, and is alone or attached elsewhere) forgets its coordinates and orientation and
  learns them again from the next packet that arrives, exactly as a module learns them the first
  time; its round waits until it has them. A module that keeps a connection keeps its coordinates.

The firmware profile (``vm.runtime_firmware``) does none of this: the firmware of 2007 runs a
program when it arrives and never looks at its connections again.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vm import navigation as nav
from vm.isa.disassembler import disassemble, reachable
from vm.isa.opcodes import PUBLISHED_SLOTS
from vm.packets import NOTIFY, PROGRAM, header_bytes, make_header
from vm.runtime_node import MAX_LOG, ModuleNode
from vm.runtime_store import PROGRAM as PROGRAM_SLOT
from vm.runtime_store import RERUN, USER_COMMAND, Slot, StoreFull

KEPT_PROGRAMS = 16


@dataclass(frozen=True, slots=True)
class Kept:
    ident: int
    code: bytes
    takes_role: bool  # SET_ROLE_NOTIFY outside a stored body: a discovery fragment
    tests_role: bool  # HAS_ROLE of a role outside a stored body: a continuation fragment
    reads_roles: bool  # CONNECTED_..._ROLE outside a stored body: invariants that read neighbour roles
    arrival: int = 0


def kept(ident: int, code: bytes, arrival: int = 0) -> Kept:
    top = reachable(code)
    names = [(d.name, d.operands) for d in disassemble(code) if d.offset in top]
    return Kept(ident, code, any(name == "SET_ROLE_NOTIFY" for name, _ in names),
                any(name == "HAS_ROLE" and ops and ops[0] != 0 for name, ops in names),
                any(name.startswith("CONNECTED_") and name.endswith("ROLE") for name, _ in names),
                arrival)


@dataclass(eq=False)
class Round:
    """One re-run of the discovery programs after a connection change."""

    start_role: int
    queue: list[Kept] = field(default_factory=list)  # still to run, in arrival order
    slot: Slot | None = None  # the program running now
    taken: int = 0  # the role taken in this round so far (what HAS_ROLE sees in it)
    decided: bool = False
    changed: bool = False
    again: bool = False  # the connections changed while it ran: another round follows


class ShapeNode(ModuleNode):
    def __init__(self, *args, **kwargs) -> None:  # noqa: ANN002, ANN003 - ModuleNode's
        super().__init__(*args, **kwargs)
        self.kept: list[Kept] = []
        self.links = frozenset(c for c in self.hal.connected_channels() if 0 <= c <= 7)
        self.link_changes: list[tuple[float, frozenset[int], frozenset[int]]] = []  # (t, lost, gained)
        self.rounds = 0
        self._round: Round | None = None
        self._round_pending = False  # a round waits for coordinates
        self._announce = False  # tell every neighbour the role once coordinates are known again
        self._loose = False  # it lost every connection: attached again, it re-learns its frame
        self._relearn: frozenset[int] = frozenset()  # connectors whose next packet gives the frame

    # ---- what the node calls ----------------------------------------------------------------
    def _keep(self, slot: Slot) -> None:
        """A received or injected program's first run ended: keep it, in arrival order (kept only
        then, so that a round never runs a program whose first run is still going on)."""
        if len(self.kept) < KEPT_PROGRAMS:  # later ones (a handler spreading, say) are not kept
            self.kept.append(kept(slot.ident, slot.code, slot.arrival))
            self.kept.sort(key=lambda k: k.arrival)

    def _neighbour_role_changed(self) -> None:
        """Invariants that read neighbour roles are checked again, once the programs that arrived
        have run (a round never runs beside a program's first run)."""
        if any(k.takes_role and k.reads_roles for k in self.kept) and not any(
                t.slot is not None and t.slot.kind == PROGRAM_SLOT for t in self.store.tasks):
            self._start_round()

    def _frame_learned(self, ch: int) -> None:
        if self._loose:  # attached again and told where it is: an ordinary module again
            self._loose, self._relearn, self._announce = False, frozenset(), True
            self.parent_channel = ch
        if self._announce:
            self._announce = False
            if self.role:
                self._notify_all(self.role)
        if self._round_pending:
            self._round_pending = False
            self._start_round()

    # ---- connections -----------------------------------------------------------------------
    def links_changed(self) -> bool:
        return self.hal.connected_channels() != self.links

    def _watch_links(self) -> None:
        now = frozenset(c for c in self.hal.connected_channels() if 0 <= c <= 7)
        if now == self.links:
            return
        old, self.links = self.links, now
        lost, gained = old - now, now - old
        self.link_changes.append((self.hal.now(), lost, gained))
        del self.link_changes[:-MAX_LOG]
        if self.parent_channel in lost:  # the tree: a new neighbour there is not its parent
            self.parent_channel = None
        self._log("links", {"lost": sorted(lost), "gained": sorted(gained)})
        for ch in lost | gained:  # a new neighbour counts its notifies and values afresh
            self._notify_seq.pop(ch, None)
            for index in range(PUBLISHED_SLOTS):
                self._value_seq.pop((ch, index), None)
        for ch in lost:
            v = self._p2v[ch]
            if self.neighbour_roles[v]:
                self.neighbour_roles[v] = 0
                self._values_changed()
        if old and not old & now:
            self._loose = not self.origin  # it may be taken anywhere: attached again, it re-learns
        if gained and self._loose:
            self._relearn |= gained
            self._round_pending = True  # its axis may have changed: check when it knows it
        elif gained and self.position is not None:
            for ch in sorted(gained):
                if self.role:
                    self._notify_id = (self._notify_id + 1) & 0xFF
                    self._send_on(ch, NOTIFY, self._notify_id, bytes((self.role & 0xFF,)))
                for program in self.kept:
                    self._send_on(ch, PROGRAM, program.ident, program.code)
        self._relearn &= now
        self._values_changed()  # programs waiting for a change (END_WAIT) check again
        if self.position is None:
            self._round_pending = True
        elif not self._round_pending:
            self._start_round()

    def _teaches(self, ch: int) -> bool:
        return ch in self._relearn

    def _send_on(self, ch: int, type_: int, ident: int, body: bytes) -> None:
        if self.position is None or self.axis is None:
            return
        x, y, z = self.position
        rx, ry, rz, raxis, rvch = nav.receiver(x, y, z, self.axis, self._p2v[ch],
                                               ud_offsets_swapped=self.target.quirks.ud_offsets_swapped)
        self.link.send(ch, header_bytes(make_header(type_, ident, rx, ry, rz, raxis, rvch)) + body)

    def _notify_all(self, role: int) -> None:
        self._notify_id = (self._notify_id + 1) & 0xFF
        self._send_all(NOTIFY, self._notify_id, bytes((role & 0xFF,)), exclude=None)

    # ---- rounds ----------------------------------------------------------------------------
    def _start_round(self) -> None:
        if not any(k.takes_role for k in self.kept):
            return
        if self._round is not None:
            self._round.again = True
            return
        self.rounds += 1
        self._round = Round(self.role, list(self.kept))
        self._round_next()

    def _round_next(self) -> None:
        """Queue the next program of the round, or end it."""
        state = self._round
        if state is None:
            return
        state.slot = None
        while state.queue:
            program = state.queue.pop(0)
            if not (program.takes_role or (program.tests_role and state.changed)):
                continue
            slot = Slot(program.code, program.ident, RERUN)
            try:
                self.store.add_and_queue(slot)
            except StoreFull as e:
                self._error(f"roles not checked again after a connection change: {e}")
                break
            state.slot = slot
            return
        self._round = None
        if not state.decided and self.role != state.start_role:
            # a program's first run gave the module a role while the round ran on the programs
            # kept before it: the round's "no role holds" is stale; check again with it kept
            state.again = True
        elif not state.decided and self.role:  # no role holds any more
            self._leave_role(0)
            self._take_role(0)
        if state.again:
            self._start_round()

    def in_round(self) -> bool:
        state = self._round
        return state is not None and state.slot is not None and self._running_slot is state.slot

    def _round_role(self, role: int) -> bool:
        """SET_ROLE_NOTIFY inside a round; False: stop this run (the module keeps its role)."""
        state = self._round
        assert state is not None
        state.decided, state.taken = True, role
        if self.roles.is_instance(self.role, role) and role:
            return False  # the role it plays (or plays with a mixin): nothing to do
        state.changed = True
        self._leave_role(role)
        return True

    def _leave_role(self, new: int) -> None:
        """What ran for roles the module no longer plays ends: behaviour and command runs, handlers,
        and the joint's motion (as the STOP command ends it). A quarter turn under way is an action
        that changes the shape, answered by ``action_result``: it finishes and says how it went."""
        keep = {id(s) for s in self.store.commands.get(new, []) if s is not None}
        running = self._running_slot
        self.store.tasks = [t for t in self.store.tasks
                            if t.slot is None or t.slot is running or t.slot.kind != USER_COMMAND
                            or id(t.slot) in keep]
        for event, vector in enumerate(self.store.vectors):
            if vector is not None and vector.slot.role and not self.roles.is_instance(new, vector.slot.role):
                self.store.clear_vector(event)
        if self.hal.is_turning() and self.hal.action_result() is not None:
            self.hal.stop_joint()  # a wheel that is no wheel any more stops turning
            self._log("joint_stopped", {"role_left": self.roles.name(self.role)})

    def _take_role(self, role: int) -> None:
        """Overridden by the runtime: set the role and tell the neighbours."""
