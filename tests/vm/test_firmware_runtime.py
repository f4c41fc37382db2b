"""vm.runtime_firmware: the firmware's controller, piece by piece (docs/firmware.md). The whole is
checked against the firmware's recorded figures in tests/firmware; these pin the rules one at a
time, with a scripted hal."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from vm_fakes import FakeHal

from vm.isa.assembler import assemble
from vm.isa.targets import DEFAULT, ORIGINAL
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_firmware import Context, FirmwareRuntime, joint_quarter, make_runtime, virtual_to_physical

ROLES = RoleTable({1: "A", 2: "B"}, {2: frozenset({1})})


def module(connected: set[int] | None = None) -> tuple[FirmwareRuntime, FakeHal]:
    hal = FakeHal(connected=set(connected or set()))
    rt = make_runtime(hal, ROLES, module_id=1, target=ORIGINAL)
    assert isinstance(rt, FirmwareRuntime)
    return rt, hal


def program_packet(code: bytes, ident: int = 0, vch: int = 0) -> bytes:
    # header: type 1, id, receiver x y z (0, 1, 1), axis UD (3), virtual channel
    return bytes((1, ident, 0, 1, 1, 3, vch)) + code


def steps(rt: FirmwareRuntime, hal: FakeHal, seconds: float, tick: float = 0.01) -> None:
    for _ in range(round(seconds / tick)):
        hal.t = round(hal.t + tick, 6)
        rt.step()


def test_only_the_original_target_runs_the_firmware_controller() -> None:
    assert isinstance(make_runtime(FakeHal(), ROLES, module_id=0, target=ORIGINAL), FirmwareRuntime)
    rt = make_runtime(FakeHal(), ROLES, module_id=0, target=DEFAULT)
    assert type(rt) is ModuleRuntime


def test_one_task_per_scheduler_step() -> None:
    rt, hal = module()
    led = assemble("SET_LED 5\nEND_TERMINATE")
    for k in range(3):
        rt.receive(0, program_packet(led, ident=k))
    assert rt.q_end - rt.q_start == 3
    steps(rt, hal, 0.02)  # the first step only reads the role (activate)
    assert rt.q_end - rt.q_start == 2 and hal.led == 5
    steps(rt, hal, 0.02)
    assert rt.q_end == rt.q_start


def test_sleep_blocks_the_module_and_its_sensors_for_a_second() -> None:
    rt, hal = module()
    body = assemble("HANDLE_EVENT 0 h 3\nSLEEP\nSET_LED 9\nEND_TERMINATE\nh: SET_LED 1\nEND_TERMINATE")
    rt.receive(0, program_packet(body))
    steps(rt, hal, 0.05)  # the handler is installed, the program sleeps
    assert rt.vectors[0] != 255 and hal.led is None
    hal.sensors = {0}
    steps(rt, hal, 0.5)
    assert hal.led is None  # blocked: nobody looked at the sensor
    hal.sensors = set()
    steps(rt, hal, 0.6)
    assert hal.led == 9  # the sleep ended; the object was never noticed


def test_a_handler_runs_inline_with_argument_0_on_every_step_while_it_sees() -> None:
    rt, hal = module()
    code = assemble("HANDLE_EVENT 2 h 3\nEND_TERMINATE\nh: PUSH_ARGUMENT 0\nEND_TERMINATE")
    rt.receive(0, program_packet(code))
    steps(rt, hal, 0.05)
    hal.sensors = {2}
    before = rt.runs
    steps(rt, hal, 0.1)
    assert rt.runs - before == 10 and rt.handler_refires == 9
    assert [e for _, kind, e in rt.event_log if kind == "handler"] == [{"event": 2}]


def test_a_full_task_queue_stops_the_module() -> None:
    rt, hal = module()
    code = assemble("END_TERMINATE")
    for k in range(9):
        rt.receive(0, program_packet(code, ident=k))
    assert not rt.halted
    rt.receive(0, program_packet(code, ident=9))
    assert rt.halted and "task queue full (error 2.0); module halted" in rt.errors[-1][1]
    rt.receive(0, program_packet(code, ident=10))  # a stopped module hears nothing
    steps(rt, hal, 0.1)
    assert len(rt.errors) == 1


def test_an_unknown_instruction_stops_the_module_with_the_pc() -> None:
    rt, hal = module()
    code = assemble("PUSH 2\nEQUALS_2\nEND_TERMINATE")
    rt.receive(0, program_packet(code))
    steps(rt, hal, 0.05)
    (error,) = rt.run_errors
    assert rt.halted and error.pc == 1 and error.code == code
    assert error.message.endswith("pc 1: unknown instruction 8 (EQUALS_2); module halted")


def test_the_entry_module_loads_fragments_8_s_apart_and_runs_none() -> None:
    rt, hal = module({0, 4})
    rt.inject(assemble("SET_LED 3\nEND_TERMINATE"))
    rt.inject(assemble("SET_LED 4\nEND_TERMINATE"))
    steps(rt, hal, 7.9)
    assert hal.sent == []
    steps(rt, hal, 0.2)
    assert [(ch, p[0], p[1]) for ch, p in hal.sent] == [(0, 1, 0), (4, 1, 0)]
    steps(rt, hal, 8.0)
    assert [(ch, p[1]) for ch, p in hal.sent[2:]] == [(0, 1), (4, 1)]
    assert hal.led is None and rt.programs_run == 0


def test_clear_event_frees_the_slot_numbered_like_the_event() -> None:
    rt, hal = module()
    code = assemble("HANDLE_EVENT 5 h 2\nCLEAR_EVENT 5\nEND_TERMINATE\nh: NOP\nEND_TERMINATE")
    rt.receive(0, program_packet(code))
    steps(rt, hal, 0.05)
    # slot 0 held the program (freed when it ended), slot 1 the handler; CLEAR_EVENT 5 flipped bit 5
    assert rt.vectors[5] == 255 and rt.use_flags == (1 << 1) | (1 << 5)


def test_sleep_rotations_counts_returns_to_the_starting_quarter() -> None:
    rt, hal = module()
    rt.receive(0, program_packet(assemble("SLEEP_ROTATIONS 1\nSET_LED 1\nEND_TERMINATE")))
    steps(rt, hal, 0.03)
    for angle in (10.0, 50.0, 140.0, -130.0, -60.0):
        hal.angle = angle
        steps(rt, hal, 0.01)
        assert hal.led is None, angle
    hal.angle = -40.0  # back in the quarter around 0°: 310° of motion
    steps(rt, hal, 0.02)
    assert hal.led == 1


def test_the_joint_quarters_are_the_simulators() -> None:
    assert [joint_quarter(a) for a in (0.0, 45.0, 46.0, 135.0, 136.0, -135.0, -44.0, 359.0)] == [
        0, 0, 1, 1, 2, 2, 0, 0]


def test_virtual_to_physical_follows_the_incoming_channels() -> None:
    identity = Context(in_vch=0, in_pch=0)
    assert [virtual_to_physical(identity, v) for v in range(8)] == list(range(8))
    rotated = Context(in_vch=0, in_pch=1)
    assert virtual_to_physical(rotated, 0) == 1
    assert sorted(virtual_to_physical(rotated, v) for v in range(8)) == list(range(8))
    crossed = Context(in_vch=2, in_pch=6)
    assert virtual_to_physical(crossed, 2) == 6
    assert sorted(virtual_to_physical(crossed, v) for v in range(8)) == list(range(8))


header = st.tuples(st.integers(0, 4), st.integers(0, 255), st.integers(-3, 3), st.integers(-3, 3),
                   st.integers(-3, 3), st.integers(0, 4), st.integers(0, 8))
packet = st.one_of(st.binary(max_size=80), st.builds(lambda h, body: bytes(v & 0xFF for v in h) + body,
                                                     header, st.binary(max_size=64)))


@settings(max_examples=400, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 9), packet), max_size=20), st.lists(st.integers(0, 7), max_size=8))
def test_garbage_packets_and_programs_never_raise(packets: list[tuple[int, bytes]],
                                                  sensors: list[int]) -> None:
    rt, hal = module({0, 1, 5})
    hal.sensors = set(sensors)
    for channel, raw in packets:
        rt.receive(channel, raw)
        steps(rt, hal, 0.03)
    steps(rt, hal, 1.5)
    assert all("internal error" not in m for _, m in rt.errors), rt.errors
    assert 0 <= rt.q_start < 10 and 0 <= rt.q_end < 10
