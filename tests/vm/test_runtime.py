"""The module runtime on one fake HAL: scheduler, suspension, events, commands, limits."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from vm_fakes import FakeHal

from vm import navigation as nav
from vm.isa.assembler import assemble
from vm.packets import (
    COMMAND,
    NOTIFY,
    PROGRAM,
    AckPacket,
    CommandPacket,
    NotifyPacket,
    decode,
    encode,
    make_header,
)
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "Wheel", 2: "LeftWheel", 3: "Axle"}, {2: frozenset({1, 2})})


def entry(connected: set[int] | None = None) -> ModuleRuntime:
    return ModuleRuntime(FakeHal(connected=set(connected or ())), ROLES, module_id=0)


def advance(vm: ModuleRuntime, seconds: float, dt: float = 0.01) -> None:
    hal = vm.hal
    assert isinstance(hal, FakeHal)
    for _ in range(round(seconds / dt)):
        vm.step()
        hal.t += dt


def test_inject_defines_the_frame_and_runs_once() -> None:
    vm = entry()
    vm.inject(assemble("SET_ROLE_NOTIFY 3\nEND_TERMINATE"))
    assert vm.position == (0, 0, 0) and vm.axis == nav.NORTH_SOUTH and vm.mapping == nav.IDENTITY
    advance(vm, 0.1)
    assert vm.role == 3 and vm.programs_run == 1 and vm.store.slots == [] and vm.store.tasks == []
    assert [k for _, k, _ in vm.event_log] == ["program", "role"]


def test_rejected_fragment_is_reported() -> None:
    vm = entry()
    vm.inject(bytes([6, 13]))
    advance(vm, 0.05)
    assert vm.programs_run == 0 and "rejected" in vm.errors[0][1]


def test_end_repeat_loops_once_per_step_and_sleep_suspends() -> None:
    vm = entry()
    vm.inject(assemble("PUSH 1\nSET_LED 1\nSLEEP\nSET_LED 2\nEND_REPEAT"))
    vm.step()
    assert vm.hal.led == 1
    advance(vm, 0.5)
    assert vm.hal.led == 1  # still asleep, stack kept
    advance(vm, 0.6)
    assert vm.hal.led in (1, 2) and len(vm.store.tasks) == 1
    assert vm.errors == []  # a fresh budget after each resume


def test_sleep_lets_other_tasks_run() -> None:
    vm = entry()
    vm.inject(assemble("SLEEP\nSET_LED 1\nEND_TERMINATE"))
    vm.inject(assemble("SET_LED 2\nEND_TERMINATE"))
    vm.step()
    assert vm.hal.led == 2
    advance(vm, 1.1)
    assert vm.hal.led == 1 and vm.store.tasks == []


def test_sleep_rotations_waits_for_joint_turns() -> None:
    vm = entry()
    vm.inject(assemble("EVAL_COMMAND ROTATE_CW 1\nSLEEP_ROTATIONS 3\nEVAL_COMMAND STOP 0\nEND_TERMINATE"))
    vm.hal.turns = 10.0
    advance(vm, 0.1)
    assert vm.hal.calls == [("rotate_continuously", 1)]
    vm.hal.turns = 12.9
    advance(vm, 0.1)
    assert len(vm.hal.calls) == 1
    vm.hal.turns = 13.0
    advance(vm, 0.02)
    assert vm.hal.calls[-1] == ("stop_joint", 0)


HANDLER = """
    HANDLE_EVENT 5 h e-h
    END_TERMINATE
h:  DISABLE_EVENT 5
    PUSH_ARGUMENT 0
    EVAL_COMMAND_STACK_ARG ROTATE_TO
    END_TERMINATE
e:
"""


def test_event_handler_fires_once_per_detection_on_the_physical_sensor() -> None:
    vm = entry()
    vm.inject(assemble(HANDLER.replace("DISABLE_EVENT 5", "NOP")))
    advance(vm, 0.05)
    assert vm.store.vectors[5] is not None and len(vm.store.slots) == 1
    vm.hal.sensors = {4}
    advance(vm, 0.05)
    assert vm.hal.calls == []
    vm.hal.sensors = {5}
    advance(vm, 0.2)
    assert vm.hal.calls == [("rotate_to", 50.0)]  # argument = event number; once while seen
    vm.hal.sensors = set()
    advance(vm, 0.05)
    vm.hal.sensors = {5}
    advance(vm, 0.05)
    assert len(vm.hal.calls) == 2
    assert [k for _, k, _ in vm.event_log].count("handler") == 2


def test_disabled_handler_does_not_fire_until_enabled() -> None:
    vm = entry()
    vm.inject(assemble(HANDLER))
    advance(vm, 0.05)
    vm.hal.sensors = {5}
    advance(vm, 0.2)
    assert len(vm.hal.calls) == 1 and not vm.store.vectors[5].enabled
    vm.inject(assemble("ENABLE_EVENT 5\nEND_TERMINATE"))
    advance(vm, 0.05)
    assert len(vm.hal.calls) == 2  # re-enabled while the object is still seen: a new detection
    vm.inject(assemble("CLEAR_EVENT 5\nEND_TERMINATE"))
    advance(vm, 0.05)
    assert vm.store.vectors[5] is None and vm.store.slots == []


INSTALL = """
    INSTALL_COMMAND 1 USER_2 c e-c
    END_TERMINATE
c:  PUSH_ARGUMENT 0
    EVAL_COMMAND_STACK_ARG ROTATE_BY
    END_TERMINATE
e:
"""


def test_user_commands_follow_the_role() -> None:
    vm = entry()
    vm.inject(assemble(INSTALL.replace("ROTATE_BY", "ROTATE_DEGREES")))
    advance(vm, 0.05)
    assert vm.store.command_slot(1, 2) is vm.store.command_slot(2, 2) is not None
    assert vm.store.command_slot(3, 2) is None
    vm.inject(assemble("EVAL_COMMAND USER_2 4\nEND_TERMINATE"))  # role none: ignored
    advance(vm, 0.05)
    assert vm.hal.calls == []
    vm.inject(assemble("SET_ROLE_NOTIFY 2\nEVAL_COMMAND USER_2 4\nEND_TERMINATE"))
    advance(vm, 0.05)
    assert vm.hal.calls == [("rotate_by", 40.0)]


def test_clear_command_queue() -> None:
    vm = entry()
    vm.inject(assemble("SET_ROLE_NOTIFY 1\nSEND_COMMAND 1 ROTATE_CW 1\nSEND_COMMAND 1 STOP 0\n"
                       "CLEAR_COMMAND_QUEUE ROTATE_CW\nEND_TERMINATE"))
    advance(vm, 0.05)
    assert vm.hal.calls == [("stop_joint", 0)]


def test_slot_and_queue_limits_are_reported() -> None:
    vm = entry()
    for i in range(11):
        vm.inject(assemble(f"SLEEP\nSET_LED {i}\nEND_TERMINATE"))
    assert len(vm.store.slots) == 10 and len(vm.store.tasks) == 10
    assert any("not accepted" in m for _, m in vm.errors)
    advance(vm, 1.2)
    assert vm.store.slots == []


def test_received_program_learns_the_frame_and_acks() -> None:
    vm = ModuleRuntime(FakeHal(connected={6, 2}), ROLES, module_id=4)
    x, y, z, r, vch = nav.receiver(0, 0, 0, nav.NORTH_SOUTH, 1)  # (-1,1,0) EW, sees sender on 3
    raw = encode_program(7, (x, y, z, r, vch), assemble("MIGRATE_CONTINUE"))
    vm.receive(6, raw)
    vm.step()
    assert vm.position == (-1, 1, 0) and vm.axis == nav.EAST_WEST
    assert vm.mapping == nav.virtual_to_physical(3, 6)
    sent = [(ch, decode(p)) for ch, p in vm.hal.sent]
    acks = [p for ch, p in sent if isinstance(p, AckPacket)]
    assert len(acks) == 1 and acks[0].header.id == 7
    vm.step()
    decoded = [(ch, decode(p)) for ch, p in vm.hal.sent]
    forwarded = [(ch, p) for ch, p in decoded if not isinstance(p, AckPacket)]
    assert [ch for ch, _ in forwarded] == [2]  # not back on the incoming channel
    h = forwarded[0][1].header
    v = vm._p2v[2]
    assert (h.x, h.y, h.z, h.r, h.vch) == nav.receiver(-1, 1, 0, nav.EAST_WEST, v)
    vm.receive(6, raw)  # a duplicate is acknowledged but not run again
    advance(vm, 0.05)
    assert vm.programs_run == 1 and vm.duplicates == 1


def encode_program(ident: int, header: tuple[int, int, int, int, int], code: bytes) -> bytes:
    from vm.packets import ProgramPacket
    return encode(ProgramPacket(make_header(PROGRAM, ident, *header), code))


def test_corrupted_header_is_dropped_silently() -> None:
    vm = ModuleRuntime(FakeHal(connected={0}), ROLES, module_id=4)
    vm.receive(0, encode_program(1, (0, 1, 0, nav.EAST_WEST, 3), assemble("END_TERMINATE")))
    vm.step()
    assert vm.position is None and vm.hal.sent == [] and vm.bad_packets == 1


def test_commands_are_forwarded_once_and_run_if_instance() -> None:
    vm = ModuleRuntime(FakeHal(connected={0, 1, 2}), ROLES, module_id=3)
    vm.role = 2
    raw = encode(CommandPacket(make_header(COMMAND, 9, *nav.receiver(0, 0, 0, 2, 1)), 1, 4, 3))
    vm.receive(1, raw)
    vm.receive(2, raw)  # the same command through a cycle
    advance(vm, 0.05)
    forwarded = [ch for ch, p in vm.hal.sent if p[0] == COMMAND]
    assert sorted(forwarded) == [0, 2]
    assert vm.hal.calls == [("rotate_by", 30.0)]


def test_notify_updates_cache_by_virtual_channel_and_ignores_older() -> None:
    vm = ModuleRuntime(FakeHal(connected={0, 1}), ROLES, module_id=3)
    vm.inject(assemble("END_TERMINATE"))  # frame: identity mapping
    h = nav.receiver(0, 0, 0, nav.NORTH_SOUTH, 1)
    vm.receive(1, encode(NotifyPacket(make_header(NOTIFY, 5, *h), 2)))
    vm.receive(1, encode(NotifyPacket(make_header(NOTIFY, 4, *h), 3)))  # older, arrives late
    vm.step()
    assert vm.neighbour_roles[1] == 2


@given(st.lists(st.tuples(st.integers(0, 9), st.binary(max_size=50)), max_size=20))
def test_random_packets_never_crash(packets: list[tuple[int, bytes]]) -> None:
    vm = entry({0, 1, 4})
    for ch, raw in packets:
        vm.receive(ch, raw)
    vm.step()
    vm.step()
    assert not any("internal error" in m for _, m in vm.errors)


@given(st.binary(min_size=1, max_size=64))
def test_random_fragments_never_crash(code: bytes) -> None:
    vm = entry({0, 5})
    vm.inject(code)
    for _ in range(3):
        vm.step()
        vm.hal.t += 1.1
    assert not any("internal error" in m for _, m in vm.errors)


def test_needs_step_and_stats() -> None:
    vm = entry({0})
    assert not vm.needs_step()
    vm.inject(assemble("SET_ROLE_NOTIFY 1\nEND_TERMINATE"))
    assert vm.needs_step()
    vm.step()
    assert vm.needs_step()  # the notify waits for its ack
    assert vm.stats()["sent"] == 1 and vm.stats()["programs_run"] == 1


def test_a_full_store_does_not_ack_so_the_program_comes_again() -> None:
    vm = entry({0})
    for i in range(10):
        vm.inject(assemble(f"SLEEP\nSET_LED {i}\nEND_TERMINATE"))
    raw = encode_program(9, nav.receiver(0, 0, 0, nav.NORTH_SOUTH, 0), assemble("SET_LED 99\nEND_TERMINATE"))
    vm.receive(0, raw)
    vm.step()
    assert not any(p[0] == 4 for _, p in vm.hal.sent)  # no ack
    advance(vm, 1.2)  # the sleepers finish, slots free
    vm.receive(0, raw)  # the sender's retry
    advance(vm, 0.05)
    assert vm.hal.led == 99 and any(p[0] == 4 for _, p in vm.hal.sent)
    assert len([m for _, m in vm.errors if "not accepted" in m]) == 1


def test_programs_run_counts_programs_not_repeats() -> None:
    vm = entry()
    vm.inject(assemble("NOP\nEND_REPEAT"))
    advance(vm, 0.1)
    assert vm.programs_run == 1 and vm.runs == 10


def test_wrong_types_from_a_world_are_not_raised() -> None:
    vm = entry()
    vm.receive(0, None)  # type: ignore[arg-type]
    vm.inject([300])  # type: ignore[arg-type]
    vm.step()
    assert vm.bad_packets == 1 and "not bytes" in vm.errors[0][1]
