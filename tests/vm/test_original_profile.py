"""The VM profile ``original`` (docs/firmware.md): one test per firmware limit and quirk, each beside
what the default profile (this project's corrected VM) does with the same code.

These run the quirk flags of ``vm.isa.targets`` in this project's interpreter and
``vm.runtime.ModuleRuntime`` (which the compiler's firmware model also uses). The worlds run a
module of this target with the firmware's own controller (``vm.runtime_firmware``, the quirk
``firmware_controller``); tests/vm/test_firmware_runtime.py and tests/firmware check that one."""

from __future__ import annotations

import pytest
from vm_fakes import FakeHal, Placed, World

from vm import navigation as nav
from vm.interpreter import Frame, Outcome, Result, run
from vm.isa.assembler import assemble
from vm.isa.opcodes import BY_OPCODE, INSTRUCTIONS
from vm.isa.targets import DEFAULT, ORIGINAL, Target
from vm.packets import ACK, COMMAND, decode
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "A", 2: "B"}, {})
MISSING = sorted(i.opcode for i in INSTRUCTIONS if not ORIGINAL.implements(i.opcode))


def module(target: Target, *, position: tuple[int, int, int] = (0, 0, 0), axis: int = nav.NORTH_SOUTH,
           mapping: tuple[int, ...] = nav.IDENTITY, connected: set[int] | None = None,
           sensors: set[int] | None = None) -> ModuleRuntime:
    hal = FakeHal(connected=set(connected or ()), sensors=set(sensors or ()))
    vm = ModuleRuntime(hal, ROLES, module_id=1, target=target)
    vm._set_frame(position, axis, mapping)
    return vm


def execute(text: str, vm: ModuleRuntime, arg: int = 0) -> tuple[Result, list[int]]:
    frame = Frame(assemble(text), arg)
    return run(frame, vm, vm.target), frame.stack


def stack_of(text: str, vm: ModuleRuntime) -> list[int]:
    result, stack = execute(text + "\nEND_TERMINATE", vm)
    assert result.outcome is Outcome.TERMINATE, result
    return stack


def test_the_missing_opcodes_are_those_of_section_10() -> None:
    assert MISSING == [8, 9, 10, 11, 19, 20, 21, 23, 28, 29, 35, 37, 38, 39, 40, 41, 50, 56, 57, 58, 59, 60,
                       61, 62, 63, 64, 65, 66, 67, 68, 69, 70, 71, 72, 73, 74, 75, 76, 77, 78, 79, 80,
                       90, 91, 92, 93, 94, 95]  # 95: ACT (issue 24)


# ---- unknown instructions halt the module --------------------------------------------------
@pytest.mark.parametrize("opcode", MISSING)
def test_an_unimplemented_opcode_halts(opcode: int) -> None:
    ins = BY_OPCODE[opcode]
    code = bytes([128 + 1, 128 + 1, opcode, *([4] * len(ins.operands)), 13])  # PUSH 1, PUSH 1, op, END
    result = run(Frame(code), module(ORIGINAL, axis=nav.NORTH_SOUTH), ORIGINAL)
    assert result.outcome is Outcome.HALT
    assert result.pc == 2
    assert result.message == f"pc 2: unknown instruction {opcode} ({ins.name})"
    assert run(Frame(code), module(DEFAULT), DEFAULT).outcome is not Outcome.HALT


def test_a_halted_module_runs_and_hears_nothing_more() -> None:
    vm = module(ORIGINAL, connected={0})
    vm.inject(assemble("PUSH 2\nEQUALS_2\nEND_TERMINATE"))
    vm.inject(assemble("SET_ROLE_NOTIFY 1\nEND_TERMINATE"))
    vm.step()
    assert vm.halted and vm.role == 0
    assert vm.errors[-1][1] == "program 1: pc 1: unknown instruction 8 (EQUALS_2); module halted"
    (err,) = vm.run_errors
    assert (err.pc, err.halted, err.code) == (1, True, assemble("PUSH 2\nEQUALS_2\nEND_TERMINATE"))
    vm.receive(0, b"\x01\x05\x00\x01\x01\x03\x06\x0d")
    assert not vm.needs_step() and not vm._inbox
    vm.step()
    assert vm.role == 0

    default = module(DEFAULT)
    default.inject(assemble("PUSH 2\nEQUALS_2\nEND_TERMINATE"))
    default.inject(assemble("SET_ROLE_NOTIFY 1\nEND_TERMINATE"))
    default.step()
    assert not default.halted and default.role == 1 and not default.errors


# ---- limits: stack 5, 100 instructions per run -------------------------------------------
def test_stack_depth_is_5() -> None:
    five, six = "PUSH 1\n" * 5, "PUSH 1\n" * 6
    assert stack_of(five, module(ORIGINAL)) == [1] * 5
    result, _ = execute(six + "END_TERMINATE", module(ORIGINAL))
    assert result.outcome is Outcome.ERROR and result.message == "pc 5: stack overflow"
    assert stack_of(six, module(DEFAULT)) == [1] * 6


def test_a_run_ends_in_error_after_100_instructions() -> None:
    ok = run(Frame(bytes([127] * 99 + [13])), module(ORIGINAL), ORIGINAL)
    assert ok.outcome is Outcome.TERMINATE
    long = bytes([127] * 100 + [13])
    too_long = run(Frame(long), module(ORIGINAL), ORIGINAL)
    assert too_long.outcome is Outcome.ERROR
    assert too_long.message == "more than 100 instructions in one run"
    assert run(Frame(long), module(DEFAULT), DEFAULT).outcome is Outcome.TERMINATE


# ---- ENABLE_EVENT toggles --------------------------------------------------------------------
HANDLER = """HANDLE_EVENT EVENT_PROXIMITY_3 body end-body
{toggles}
END_TERMINATE
body:
PUSH_ARGUMENT 0
PUSH 4
APPLY
END_TERMINATE
end:
"""


@pytest.mark.parametrize(("toggles", "original", "default"), [
    ("ENABLE_EVENT EVENT_PROXIMITY_3", False, True),  # enabling an enabled handler disables it
    ("DISABLE_EVENT EVENT_PROXIMITY_3\nENABLE_EVENT EVENT_PROXIMITY_3", True, True),
    ("ENABLE_EVENT EVENT_PROXIMITY_3\nENABLE_EVENT EVENT_PROXIMITY_3", True, True),
    ("DISABLE_EVENT EVENT_PROXIMITY_3", False, False),
])
def test_enable_event_toggles(toggles: str, original: bool, default: bool) -> None:
    for target, enabled in ((ORIGINAL, original), (DEFAULT, default)):
        vm = module(target)
        assert execute(HANDLER.format(toggles=toggles), vm)[0].outcome is Outcome.TERMINATE
        vector = vm.store.vectors[3]
        assert vector is not None and vector.enabled is enabled, target.name


# ---- handlers re-fire with argument 0 --------------------------------------------------------
def test_a_handler_runs_with_argument_0_on_every_step_while_its_sensor_sees() -> None:
    runs = {}
    for target in (ORIGINAL, DEFAULT):
        vm = module(target, sensors={3})
        vm.inject(assemble(HANDLER.format(toggles="")))
        for _ in range(5):
            vm.step()
        runs[target.name] = [c for c in vm.hal.calls if c[0] == "rotate_by"]  # type: ignore[attr-defined]
        assert sum(1 for _, kind, _ in vm.event_log if kind == "handler") == 1  # one detection
    # the first step installs the handler; each of the 4 others runs it: ROTATE_DEGREES with argument 0
    assert runs["original"] == [("rotate_by", 0.0)] * 4
    assert runs["default"] == [("rotate_by", 30.0)]  # once, with the event number


def test_a_handler_that_disables_its_event_runs_once_in_both_profiles() -> None:
    code = HANDLER.replace("body:\n", "body:\nDISABLE_EVENT EVENT_PROXIMITY_3\n").format(toggles="")
    for target in (ORIGINAL, DEFAULT):
        vm = module(target, sensors={3})
        vm.inject(assemble(code))
        for _ in range(5):
            vm.step()
        assert len([c for c in vm.hal.calls if c[0] == "rotate_by"]) == 1  # type: ignore[attr-defined]


# ---- APPLY with f = 64 -----------------------------------------------------------------------
def test_apply_64_broadcasts_command_a_to_every_role() -> None:
    vm = module(ORIGINAL, connected={0, 5})
    assert stack_of("PUSH 3\nPUSH 64\nAPPLY", vm) == [0]  # command 3 (STOP) to every role
    commands = [decode(p) for _, p in vm.hal.sent]  # type: ignore[attr-defined]
    assert sorted(ch for ch, _ in vm.hal.sent) == [0, 5]  # type: ignore[attr-defined]
    assert all(p.header.type == COMMAND and (p.role, p.command, p.argument) == (255, 3, 0)
               for p in commands)  # type: ignore[union-attr]
    vm.step()
    assert ("stop_joint", 0) in vm.hal.calls  # type: ignore[attr-defined]

    default = module(DEFAULT, connected={0, 5})
    assert stack_of("PUSH 3\nPUSH 64\nAPPLY", default) == [0]
    assert not default.hal.sent and default.errors[-1][1] == "unknown command 64"  # type: ignore[attr-defined]


# ---- CONNECTED: physical channels, bit p+1 ----------------------------------------------------
def test_connected_sets_bit_p_plus_1_of_physical_channels_and_loses_7() -> None:
    mapping = nav.virtual_to_physical(0, 4)
    for connected, original in (({4, 7}, 0b10_0000), ({0, 3}, 0b1_0010), ({7}, 0), ({6, 7}, -128)):
        vm = module(ORIGINAL, mapping=mapping, connected=connected)
        virtual = nav.map_connset(sum(1 << p for p in connected), nav.invert(mapping))
        assert stack_of("CONNECTED", vm) == [original]
        assert stack_of("CONNECTED", module(DEFAULT, mapping=mapping, connected=connected)) == [
            virtual - 256 if virtual > 127 else virtual]
        assert stack_of("CONNECTED_SIZEOF", vm) == [len(connected)]  # counts right on both


# ---- CONNECTED_DIR_SIZEOF: the bits of the count, only some axis/direction pairs ---------------
@pytest.mark.parametrize(("axis", "position", "direction", "connected", "original", "default"), [
    (nav.EAST_WEST, (1, 1, 0), "UP", {0, 4}, 1, 2),  # 2 reads as 1
    (nav.EAST_WEST, (1, 1, 0), "EAST", {0, 1, 2}, 2, 3),
    (nav.EAST_WEST, (1, 1, 0), "EAST", {0, 1, 2, 3}, 1, 4),  # 4 reads as 1
    (nav.EAST_WEST, (1, 1, 0), "DOWN", {2}, 1, 1),
    (nav.NORTH_SOUTH, (0, 0, 0), "NORTH", {0, 1, 2}, 2, 3),
    (nav.NORTH_SOUTH, (0, 0, 0), "DOWN", set(), 0, 0),
])
def test_connected_dir_sizeof_counts_the_bits_of_the_count(axis: int, position: tuple[int, int, int],
                                                           direction: str, connected: set[int],
                                                           original: int, default: int) -> None:
    code = f"CONNECTED_DIR_SIZEOF {direction}"
    assert stack_of(code, module(ORIGINAL, position=position, axis=axis, connected=connected)) == [original]
    assert stack_of(code, module(DEFAULT, position=position, axis=axis, connected=connected)) == [default]


@pytest.mark.parametrize(("axis", "position", "direction"), [
    (nav.NORTH_SOUTH, (0, 0, 0), "EAST"), (nav.NORTH_SOUTH, (0, 0, 0), "UP"),
    (nav.NORTH_SOUTH, (0, 0, 0), "SOUTH"), (nav.EAST_WEST, (1, 1, 0), "SOUTH"),
    (nav.UP_DOWN, (0, 1, 1), "DOWN"), (nav.UP_DOWN, (0, 1, 1), "NORTH"),
])
def test_connected_dir_sizeof_halts_where_the_firmware_does_not_support_it(
        axis: int, position: tuple[int, int, int], direction: str) -> None:
    result, _ = execute(f"CONNECTED_DIR_SIZEOF {direction}\nEND_TERMINATE",
                        module(ORIGINAL, position=position, axis=axis, connected={0}))
    assert result.outcome is Outcome.HALT and "not supported" in result.message
    assert stack_of(f"CONNECTED_DIR_SIZEOF {direction}", module(DEFAULT, position=position, axis=axis)) == [0]


# ---- the UD 5/7 x-offsets ----------------------------------------------------------------------
def test_ud_channels_5_and_7_tell_the_receiver_the_wrong_x() -> None:
    for v in range(8):
        right = nav.receiver(0, 1, 1, nav.UP_DOWN, v)
        wrong = nav.receiver(0, 1, 1, nav.UP_DOWN, v, ud_offsets_swapped=True)
        if v in (5, 7):
            assert wrong == (-right[0], *right[1:])
        else:
            assert wrong == right
    for axis, pos in ((nav.NORTH_SOUTH, (0, 0, 0)), (nav.EAST_WEST, (1, 1, 0))):
        assert all(nav.receiver(*pos, axis, v, ud_offsets_swapped=True) == nav.receiver(*pos, axis, v)
                   for v in range(8))


def _axle_and_wheel() -> list[Placed]:
    """Entry NS at the origin, a UD axle below-north, an EW wheel on the axle's channel 5."""
    ud = nav.receiver(0, 0, 0, nav.NORTH_SOUTH, 2)
    wheel = nav.receiver(*ud[:3], nav.UP_DOWN, 5)
    return [Placed((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY), Placed(ud[:3], nav.UP_DOWN, nav.IDENTITY),
            Placed(wheel[:3], nav.EAST_WEST, nav.IDENTITY)]


def test_a_module_reached_through_ud_channel_5_learns_a_wrong_x() -> None:
    placed = _axle_and_wheel()
    for target, x in ((ORIGINAL, -placed[2].position[0]), (DEFAULT, placed[2].position[0])):
        world = World(placed, ROLES, target=target)
        world.vms[0].inject(assemble("MIGRATE_CONTINUE"))
        world.run(0.2)
        assert world.vms[2].position == (x, *placed[2].position[1:]), target.name
        assert world.vms[2].axis == nav.EAST_WEST  # the axis and the channel mapping stay right


# ---- no duplicate suppression, no acknowledgements --------------------------------------------
def _ring() -> list[Placed]:
    """Four modules in a cycle: NS (0,0,0), EW (1,1,0), NS (2,0,0), EW (1,-1,0)."""
    return [Placed((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY), Placed((1, 1, 0), nav.EAST_WEST, nav.IDENTITY),
            Placed((2, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY), Placed((1, -1, 0), nav.EAST_WEST, nav.IDENTITY)]


def _accepted(vm: ModuleRuntime) -> int:
    return sum(1 for _, kind, _ in vm.event_log if kind == "program")


def test_programs_circulate_in_a_cycle_without_duplicate_suppression() -> None:
    original, default = World(_ring(), ROLES, target=ORIGINAL), World(_ring(), ROLES)
    for world in (original, default):
        world.vms[0].inject(assemble("MIGRATE_CONTINUE"))
        world.run(1.0)
    assert [_accepted(vm) for vm in default.vms] == [1, 1, 1, 1]
    assert all(_accepted(vm) > 10 for vm in original.vms)  # still going round after a second
    assert original.in_flight  # and it never stops


def test_a_cycle_fills_the_task_queue_with_a_repeating_program() -> None:
    """A behaviour as the compiler emits it (install the repeating body as a command, start it,
    spread) starts one more repeating task on every lap until the queue or the store is full."""
    code = assemble("""SET_ROLE_NOTIFY 1
INSTALL_COMMAND 1 USER_1 body end-body
EVAL_COMMAND USER_1 0
MIGRATE_CONTINUE
body:
SLEEP
END_REPEAT
end:""")
    world = World(_ring(), ROLES, target=ORIGINAL)
    world.vms[0].inject(code)
    world.run(3.0)
    messages = [m for vm in world.vms for _, m in vm.errors]
    assert any("not accepted" in m and ("queue full" in m or "slots are in use" in m) for m in messages)
    default = World(_ring(), ROLES)
    default.vms[0].inject(code)
    default.run(3.0)
    assert not any(vm.errors for vm in default.vms)


def test_commands_circulate_in_a_cycle_without_duplicate_suppression() -> None:
    for target, bounded in ((ORIGINAL, False), (DEFAULT, True)):
        world = World(_ring(), ROLES, target=target)
        world.vms[0].inject(assemble("SEND_COMMAND ANY STOP 0\nEND_TERMINATE"))
        world.run(1.0)
        stops = [sum(1 for c in h.calls if c[0] == "stop_joint") for h in world.hals]
        assert (max(stops) == 1) is bounded, (target.name, stops)


def test_the_firmware_sends_each_packet_once_and_never_acknowledges() -> None:
    for target, acks in ((ORIGINAL, False), (DEFAULT, True)):
        world = World(_ring()[:2], ROLES, target=target, loss=1.0)  # every packet lost
        world.vms[0].inject(assemble("MIGRATE_CONTINUE"))
        world.run(2.0)
        sent = world.hals[0].sent
        assert (len(sent) > 1) is acks, target.name  # retransmissions only with acks
    world = World(_ring()[:2], ROLES, target=ORIGINAL)
    world.vms[0].inject(assemble("MIGRATE_CONTINUE"))
    world.run(0.5)
    assert _accepted(world.vms[1]) == 1
    assert not any(decode(p).header.type == ACK for h in world.hals for _, p in h.sent)  # type: ignore[union-attr]
