"""Semantics of each instruction (docs/vm.md), run by the interpreter against a real module
runtime on a fake HAL."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from vm_fakes import FakeHal

from vm import navigation as nav
from vm.interpreter import Frame, Outcome, Result, run
from vm.isa.assembler import assemble
from vm.isa.opcodes import INSTRUCTIONS, Operand
from vm.packets import NotifyPacket, decode
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "Wheel", 2: "LeftWheel", 3: "Axle"}, {2: frozenset({1, 2})})


def module(position: tuple[int, int, int] = (0, 0, 0), axis: int = nav.NORTH_SOUTH,
           mapping: tuple[int, ...] = nav.IDENTITY, connected: set[int] | None = None,
           role: int = 0) -> ModuleRuntime:
    hal = FakeHal(connected=set(connected or ()))
    vm = ModuleRuntime(hal, ROLES, module_id=1)
    vm._set_frame(position, axis, mapping)
    vm.role = role
    return vm


def execute(text: str, vm: ModuleRuntime | None = None,
            arg: int = 0) -> tuple[Result, list[int], ModuleRuntime]:
    vm = vm or module()
    frame = Frame(assemble(text), arg)
    result = run(frame, vm)
    return result, frame.stack, vm


def stack_of(text: str, vm: ModuleRuntime | None = None, arg: int = 0) -> list[int]:
    result, stack, _ = execute(text + "\nEND_TERMINATE", vm, arg)
    assert result.outcome is Outcome.TERMINATE, result
    return stack


@pytest.mark.parametrize(("axis", "expected"), [(nav.EAST_WEST, [1, 0, 0]), (nav.NORTH_SOUTH, [0, 1, 0]),
                                                (nav.UP_DOWN, [0, 0, 1])])
def test_center_position(axis: int, expected: list[int]) -> None:
    pos = {nav.EAST_WEST: (1, 1, 0), nav.NORTH_SOUTH: (0, 0, 0), nav.UP_DOWN: (0, 1, 1)}[axis]
    vm = module(pos, axis)
    assert stack_of("CENTER_POSITION_EW\nCENTER_POSITION_NS\nCENTER_POSITION_UD", vm) == expected


def test_connected_maps_physical_to_virtual() -> None:
    mapping = nav.virtual_to_physical(0, 4)  # virtual 0 is physical 4, virtual 1 is physical 7
    vm = module(mapping=mapping, connected={4, 7})
    assert stack_of("CONNECTED\nCONNECTED_SIZEOF", vm) == [0b11, 2]


def test_connset_of_channel_7_is_a_negative_byte() -> None:
    vm = module(connected={7})
    assert stack_of("CONNECTED\nSIZEOF", vm) == [1]
    assert stack_of("CONNECTED", vm) == [-128]


@pytest.mark.parametrize("k", range(5))
def test_equals_k(k: int) -> None:
    op = f"EQUALS_{k}"
    assert stack_of(f"PUSH {k}\n{op}\nPUSH {k + 1}\n{op}") == [1, 0]


def test_connected_dir() -> None:
    vm = module((1, 1, 0), nav.EAST_WEST, connected={0, 2, 5})  # EW: UP={0,4}, DOWN={2,6}, NORTH={1,5}
    assert stack_of("CONNECTED_DIR UP\nCONNECTED_DIR DOWN\nCONNECTED_DIR NORTH\nCONNECTED_DIR_SIZEOF EAST",
                    vm) == [1, 4, 32, 2]


def test_endings() -> None:
    assert execute("END_TERMINATE")[0].outcome is Outcome.TERMINATE
    assert execute("END_REPEAT")[0].outcome is Outcome.REPEAT
    assert execute("MIGRATE_CONTINUE")[0].outcome is Outcome.MIGRATE
    assert execute("SLEEP\nEND_TERMINATE")[0].outcome is Outcome.SLEEP
    result = execute("SLEEP_ROTATIONS 3\nEND_TERMINATE")[0]
    assert result.outcome is Outcome.SLEEP_ROTATIONS and result.turns == 3


def test_jumps() -> None:
    text = """
        PUSH 0
        IF_FALSE_GOTO a
        PUSH 9
    a:  PUSH 1
        IF_TRUE_GOTO b
        PUSH 9
    b:  PUSH 1
        IF_FALSE_GOTO c
        PUSH 5
        GOTO c
        PUSH 9
    c:  PUSH 0
        IF_TRUE_GOTO d
        PUSH 6
    d:  NOP
    """
    assert stack_of(text) == [5, 6]


def test_set_role_notify_sends_receiver_coordinates() -> None:
    vm = module(connected={1, 6})
    _, _, vm = execute("SET_ROLE_NOTIFY 3\nEND_TERMINATE", vm)
    assert vm.role == 3 and vm.role_history == [(0.0, 3)]
    sent = {ch: decode(raw) for ch, raw in vm.hal.sent}
    assert set(sent) == {1, 6}
    p = sent[1]
    assert isinstance(p, NotifyPacket) and p.role == 3
    h = p.header
    assert (h.x, h.y, h.z, h.r, h.vch) == nav.receiver(0, 0, 0, nav.NORTH_SOUTH, 1)


def test_coordinates_and_comparisons() -> None:
    vm = module((-2, 4, 0), nav.NORTH_SOUTH)
    assert stack_of("COORD_X\nCOORD_Y\nCOORD_Z", vm) == [-2, 4, 0]
    compare = "PUSH 3\nPUSH 2\nGREATER\nPUSH 3\nPUSH 2\nLESSER\nPUSH 2\nPUSH 2\nGREATER"
    assert stack_of(compare, vm) == [1, 0, 0]
    text = ("PUSH 0\nCOORD_X_GREATER\nPUSH 0\nCOORD_X_LESSER\nPUSH 3\nCOORD_Y_GREATER\n"
            "PUSH 5\nCOORD_Y_LESSER\nPUSH 0\nCOORD_Z_GREATER\nPUSH 1\nCOORD_Z_LESSER")
    assert stack_of(text, vm) == [0, 1, 1, 1, 0, 1]
    assert stack_of("PUSHC -3\nCOORD_X_LESSER", vm) == [0]


def test_has_role_uses_instance_of() -> None:
    vm = module(role=2)
    assert stack_of("HAS_ROLE 2\nHAS_ROLE 1\nHAS_ROLE 3\nHAS_ROLE ANY", vm) == [1, 1, 0, 1]
    assert stack_of("HAS_ROLE 0\nHAS_ROLE ANY", module()) == [1, 1]


def test_connected_role_reads_the_neighbour_cache() -> None:
    vm = module((1, 1, 0), nav.EAST_WEST, connected={0, 2, 4})  # UP={0,4}, DOWN={2,6}
    vm.neighbour_roles[0] = 2
    vm.neighbour_roles[4] = 3
    vm.neighbour_roles[2] = 1
    vm.neighbour_roles[6] = 1  # not connected
    assert stack_of("CONNECTED_ROLE UP 1\nCONNECTED_ROLE UP ANY\nCONNECTED_ROLE DOWN 2", vm) == [1, 17, 0]
    text = ("CONNECTED_UP_ROLE 3\nCONNECTED_DOWN_ROLE 1\nCONNECTED_EAST_ROLE 1\nCONNECTED_WEST_ROLE 1\n"
            "CONNECTED_NORTH_ROLE 2\nCONNECTED_SOUTH_ROLE 2")
    # EW: EAST={0,1,2,3}, WEST={4..7}, NORTH={1,5}, SOUTH={3,7}
    assert stack_of(text, vm) == [1, 1, 1, 0, 0, 0]


@pytest.mark.parametrize(("cmd", "arg", "call"), [
    (1, 2, ("rotate_continuously", 2)), (2, 1, ("rotate_continuously", -1)), (3, 0, ("stop_joint", 0)),
    (4, 9, ("rotate_by", 90.0)), (5, -9, ("rotate_to", -90.0)), (1, 0, ("rotate_continuously", 1)),
])
def test_eval_command_drives_the_joint(cmd: int, arg: int, call: tuple[str, float]) -> None:
    _, _, vm = execute(f"EVAL_COMMAND {cmd} {arg}\nEND_TERMINATE")
    assert vm.hal.calls == [call]
    _, _, vm = execute(f"PUSHC {arg}\nEVAL_COMMAND_STACK_ARG {cmd}\nEND_TERMINATE")
    assert vm.hal.calls == [call]
    assert stack_of(f"PUSHC {arg}\nPUSH {cmd}\nAPPLY", vm := module()) == [0]
    assert vm.hal.calls == [call]


def test_apply_with_a_bad_command_is_an_error_not_a_crash() -> None:
    stack_of("PUSH 0\nPUSH 77\nAPPLY", vm := module())
    assert vm.errors and "unknown command 77" in vm.errors[0][1]


def test_stack_ops() -> None:
    assert stack_of("PUSH 7\nNEGATE\nPUSHC -128\nNEGATE") == [-7, 127]  # saturates
    assert stack_of("PUSHC 0x0F\nSIZEOF\nPUSHC -1\nSIZEOF") == [4, 8]
    assert stack_of("PUSH 3\nPUSH 3\nEQUALS\nPUSH 3\nPUSH 4\nEQUALS") == [1, 0]
    assert stack_of("PUSH 100\nPUSH 100\nADD\nPUSH 1\nPUSH 3\nSUB") == [127, -2]  # saturates
    assert stack_of("PUSHC 200\nPUSH 127") == [-56, 127]
    assert stack_of("PUSH_ARGUMENT 0", arg=-5) == [-5]
    assert stack_of("NOP") == []


def test_set_led_and_debug_trace() -> None:
    _, _, vm = execute("ACTIVATE_DEBUG\nSET_LED 5\nEND_TERMINATE")
    assert vm.hal.led == 5
    assert [k for _, k, _ in vm.event_log].count("trace") == 2


def test_send_command_floods_and_runs_locally_if_instance() -> None:
    vm = module(connected={0, 3}, role=2)
    _, _, vm = execute("SEND_COMMAND 1 ROTATE_CW 2\nEND_TERMINATE", vm)
    assert sorted(ch for ch, _ in vm.hal.sent) == [0, 3]
    assert [t.command for t in vm.store.tasks] == [1]
    vm2 = module(connected={0}, role=3)
    _, _, vm2 = execute("PUSH 4\nSEND_COMMAND_STACK_ARG 1 ROTATE_CW\nEND_TERMINATE", vm2)
    assert vm2.store.tasks == [] and len(vm2.hal.sent) == 1


def test_runtime_errors_of_unverified_code() -> None:
    assert "underflow" in execute("EQUALS_0")[0].message
    assert "overflow" in execute("\n".join(["PUSH 1"] * 17))[0].message
    result = execute("l: GOTO l")[0]
    assert result.outcome is Outcome.ERROR and "255" in result.message
    assert execute(".byte 0")[0].outcome is Outcome.ERROR
    assert execute(".byte 16")[0].outcome is Outcome.ERROR  # operand missing
    assert execute("NOP")[0].outcome is Outcome.ERROR  # falls off the end


@given(st.binary(max_size=64), st.integers(-128, 127))
def test_any_bytes_run_safely(code: bytes, arg: int) -> None:
    vm = module(connected={0, 5})
    result = run(Frame(code, arg), vm)
    assert isinstance(result.outcome, Outcome)


def test_every_opcode_is_dispatched() -> None:
    values = {Operand.DIR: nav.UP, Operand.ZERO: 0, Operand.COMMAND: 3, Operand.EVENT: 1,
              Operand.START: 0, Operand.SIZE: 1, Operand.TARGET: 0}
    for ins in INSTRUCTIONS:
        code = bytes([128, 128, ins.opcode, *(values.get(k, 1) for k in ins.operands), 13])
        result = run(Frame(code), module(connected={0}))
        assert "unknown" not in result.message, ins.name
