"""The state extension of the VM (issue 17): LOAD_STATE, STORE_STATE and publishing, NBR_AGG over
the neighbours' value cache, MIN, MAX, saturating arithmetic, RUN_LOCAL, END_WAIT and the value
packet (type 5)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from vm_fakes import FakeHal

from vm import navigation as nav
from vm.interpreter import Frame, Outcome, run
from vm.isa.assembler import assemble
from vm.isa.opcodes import STATE_SLOTS, saturated
from vm.isa.targets import ORIGINAL
from vm.isa.verifier import verify
from vm.packets import PROGRAM, VALUE, PacketError, ProgramPacket, ValuePacket, decode, encode, make_header
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "Node"}, {})


def module(connected: set[int] | None = None) -> ModuleRuntime:
    vm = ModuleRuntime(FakeHal(connected=set(connected or ())), ROLES, module_id=1)
    vm._set_frame((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY)
    return vm


def stack_of(text: str, vm: ModuleRuntime) -> list[int]:
    frame = Frame(assemble(text + "\nEND_TERMINATE"))
    assert run(frame, vm).outcome is Outcome.TERMINATE
    return frame.stack


def values_sent(vm: ModuleRuntime) -> list[tuple[int, ValuePacket]]:
    found = []
    for channel, raw in vm.hal.sent:  # type: ignore[attr-defined]
        packet = decode(raw)
        if isinstance(packet, ValuePacket):
            found.append((channel, packet))
    return found


def test_store_then_load() -> None:
    vm = module()
    assert stack_of("PUSH 42\nSTORE_STATE 20\nLOAD_STATE 20\nLOAD_STATE 3", vm) == [42, 0]
    assert vm.state[20] == 42 and vm.state_history[-1][1:] == (20, 42)


def test_writes_in_one_instant_are_one_change_in_the_history() -> None:
    vm = module()
    stack_of("PUSH 5\nSTORE_STATE 9\nPUSH 6\nSTORE_STATE 9", vm)  # one instant: the value at its end
    assert vm.state_history == [(0.0, 9, 6)]
    vm.hal.t = 1.0  # type: ignore[attr-defined]
    stack_of("PUSH -50\nSTORE_STATE 9\nPUSH 6\nSTORE_STATE 9", vm)  # back to 6: no change
    assert vm.state_history == [(0.0, 9, 6)]
    stack_of("PUSH 1\nSTORE_STATE 10\nPUSH 7\nSTORE_STATE 9\nPUSH 8\nSTORE_STATE 9", vm)
    assert vm.state_history == [(0.0, 9, 6), (1.0, 10, 1), (1.0, 9, 8)]
    vm.hal.t = 2.0  # type: ignore[attr-defined]
    stack_of("PUSH 9\nSTORE_STATE 9", vm)
    assert vm.state_history[-1] == (2.0, 9, 9) and len(vm.state_history) == 4


def test_a_published_state_is_sent_once_per_change_to_every_neighbour() -> None:
    vm = module(connected={0, 5})
    stack_of("PUSH 7\nSTORE_STATE 2\nPUSH 7\nSTORE_STATE 2\nPUSH 8\nSTORE_STATE 2", vm)
    sent = values_sent(vm)
    assert [(ch, p.index, p.value) for ch, p in sent] == [(0, 2, 7), (5, 2, 7), (0, 2, 8), (5, 2, 8)]


def test_state_8_and_above_is_not_published() -> None:
    vm = module(connected={0})
    stack_of("PUSH 7\nSTORE_STATE 8", vm)
    assert values_sent(vm) == []


def test_the_first_store_is_published_even_when_it_keeps_the_value() -> None:
    vm = module(connected={1})
    stack_of("PUSH 0\nSTORE_STATE 0", vm)
    assert [(p.index, p.value) for _, p in values_sent(vm)] == [(0, 0)]


def test_the_parent_is_the_channel_of_the_first_program() -> None:
    vm = ModuleRuntime(FakeHal(connected={2, 6}), ROLES, module_id=1)
    header = make_header(VALUE, 1, 0, 1, 1, nav.UP_DOWN, 6)  # a neighbour's value: sets the frame
    vm.receive(6, encode(ValuePacket(header, 0, False, 5)))
    vm.step()
    assert vm.parent_channel is None  # a value packet is not a program
    program = encode(ProgramPacket(make_header(PROGRAM, 7, 0, 1, 1, nav.UP_DOWN, 2),
                                   assemble("END_TERMINATE")))
    vm.receive(2, program)
    vm.step()
    assert vm.parent_channel == 2
    stack_of("PUSH 3\nSTORE_STATE 1", vm)
    flags = {ch: p.to_parent for ch, p in values_sent(vm) if p.index == 1}
    assert flags == {2: True, 6: False}


def _receive_value(vm: ModuleRuntime, channel: int, index: int, value: int, ident: int,
                   to_parent: bool = False) -> None:
    x, y, z, r, vch = nav.receiver(0, 0, 0, nav.NORTH_SOUTH, channel)  # what the neighbour computes
    header = make_header(VALUE, ident, x, y, z, r, vch)
    vm.receive(channel, encode(ValuePacket(header, index, to_parent, value)))
    vm.step()


@pytest.mark.parametrize(("gather", "expected"), [(0x00, 2), (0x10, 9), (0x20, 3), (0x30, 16)])
def test_aggregates(gather: int, expected: int) -> None:
    vm = module(connected={0, 1, 4, 5})
    for ident, (channel, value) in enumerate(((0, 5), (1, 9), (4, 2)), start=1):
        _receive_value(vm, channel, 0, value, ident)
    assert stack_of(f"NBR_AGG {gather} 0", vm) == [expected]


def test_aggregates_of_no_values() -> None:
    vm = module(connected={0})
    assert stack_of("NBR_AGG 0 0\nNBR_AGG 16 0\nNBR_AGG 32 0\nNBR_AGG 48 0", vm) == [127, -128, 0, 0]


def test_where_selects_children_a_direction_or_a_connector() -> None:
    vm = module(connected={0, 1, 4})
    _receive_value(vm, 0, 1, 10, 1, to_parent=True)
    _receive_value(vm, 1, 1, 20, 2)
    _receive_value(vm, 4, 1, 40, 3, to_parent=True)
    up = 8  # UP
    assert stack_of("NBR_AGG 0x31 1", vm) == [50]  # sum over the children
    assert stack_of(f"NBR_AGG 0x31 {up}", vm) == [sum(v for ch, v in ((0, 10), (1, 20), (4, 40))
                                                       if nav.channels_facing(nav.NORTH_SOUTH, up) >> ch & 1)]
    assert stack_of("NBR_AGG 0x01 17", vm) == [20]  # connector 1
    assert stack_of("NBR_AGG 0x21 18", vm) == [0]  # connector 2: nobody there


def test_an_older_value_never_overwrites_a_newer_one() -> None:
    vm = module(connected={0})
    _receive_value(vm, 0, 0, 5, 10)
    _receive_value(vm, 0, 0, 4, 9)  # a retransmitted, older packet
    assert stack_of("NBR_AGG 0 0", vm) == [5]


def test_a_lost_neighbour_is_forgotten() -> None:
    vm = module(connected={0, 1})
    _receive_value(vm, 0, 0, 5, 1)
    _receive_value(vm, 1, 0, 9, 2)
    vm.hal.connected.discard(0)  # type: ignore[attr-defined]
    assert vm.needs_step()
    vm.step()
    assert stack_of("NBR_AGG 0x20 0\nNBR_AGG 0 0", vm) == [1, 9]


@given(st.integers(-128, 127), st.integers(-128, 127))
def test_arithmetic_saturates(a: int, b: int) -> None:
    vm = module()
    pair = f"PUSHC {a}\nPUSHC {b}\n"
    text = f"{pair}ADD\n{pair}SUB\n{pair}MIN\n{pair}MAX"
    assert stack_of(text, vm) == [saturated(a + b), saturated(a - b), min(a, b), max(a, b)]


def test_end_wait_sleeps_until_a_value_changes() -> None:
    vm = module(connected={0})
    code = assemble("LOAD_STATE 9\nPUSH 1\nADD\nSTORE_STATE 9\nEND_WAIT")
    vm.run_local(code)
    vm.step()
    assert vm.state[9] == 1  # a run that changed a value runs again, like END_REPEAT
    vm.step()
    assert vm.state[9] == 2 and not any(t.waiting for t in vm.store.tasks)
    waiting = assemble("NBR_AGG 0 0\nSTORE_STATE 10\nEND_WAIT")
    vm.store.tasks.clear()
    vm.run_local(waiting)
    vm.step()
    vm.step()  # the first run changed state 10, so it ran again; the second changed nothing
    assert vm.state[10] == 127 and all(t.waiting for t in vm.store.tasks)
    assert not vm.needs_step()
    _receive_value(vm, 0, 0, 3, 1)
    vm.step()
    assert vm.state[10] == 3


def test_run_local_keeps_one_copy_of_the_same_code() -> None:
    vm = module()
    code = assemble("NBR_AGG 0 0\nSTORE_STATE 10\nEND_WAIT")
    vm.run_local(code)
    vm.run_local(code)
    assert sum(1 for s in vm.store.slots if s.code == code) == 1


def test_state_operands_are_checked() -> None:
    assert verify(bytes((61, STATE_SLOTS, 13)))  # LOAD_STATE 32
    assert verify(bytes((63, 0x08, 0, 13)))  # NBR_AGG of state 8
    assert verify(bytes((63, 0x00, 2, 13)))  # NBR_AGG where 2
    assert verify(bytes((61, 3, 13))) == []


def test_the_original_profile_halts_on_state_instructions() -> None:
    vm = module()
    frame = Frame(assemble("PUSH 1\nSTORE_STATE 0\nEND_TERMINATE"))
    result = run(frame, vm, ORIGINAL)
    assert result.outcome is Outcome.HALT and "unknown instruction 62" in result.message


@given(st.binary(min_size=0, max_size=12))
def test_value_packets_decode_or_fail_cleanly(body: bytes) -> None:
    raw = bytes((VALUE, 1, 0, 0, 0, nav.NORTH_SOUTH, 0)) + body
    packet = decode(raw)
    if len(body) == 2 and body[0] & 0x7F < 8:
        assert isinstance(packet, ValuePacket) and encode(packet) == raw
    else:
        assert isinstance(packet, PacketError)


def test_a_program_carries_a_value_that_it_can_change() -> None:
    vm = module(connected={0, 4})
    code = assemble("LOAD_DATA\nSTORE_STATE 0\nLOAD_DATA\nPUSH 1\nADD\nSTORE_DATA\nMIGRATE_CONTINUE\nDATA 5")
    vm.inject(code)
    vm.step()
    assert vm.state[0] == 5
    sent = [decode(raw) for _, raw in vm.hal.sent]  # type: ignore[attr-defined]
    programs = [p for p in sent if type(p).__name__ == "ProgramPacket"]
    assert programs and all(p.code[-1] == 6 and p.code[:-1] == code[:-1] for p in programs)


def test_copies_that_differ_only_in_the_carried_value_are_one_program() -> None:
    from vm.runtime_node import program_key

    code = assemble("LOAD_DATA\nSTORE_STATE 0\nMIGRATE_CONTINUE\nDATA 5")
    other = code[:-1] + bytes((9,))
    assert program_key(code) == program_key(other) != code
    plain = assemble("PUSH 69\nPUSH 5\nEND_TERMINATE")  # bytes 69, 5 inside: not a DATA ending
    assert program_key(plain) == plain


def test_data_must_end_the_fragment_and_is_never_run() -> None:
    assert verify(assemble("LOAD_DATA\nSTORE_DATA\nEND_TERMINATE\nDATA 1")) == []
    assert verify(assemble("PUSH 1\nDATA 1"))  # control falls into it
    assert verify(assemble("END_TERMINATE\nDATA 1\nEND_TERMINATE"))  # not last
    vm = module()
    assert stack_of("LOAD_DATA", vm) == [0]  # a program that carries nothing reads 0
