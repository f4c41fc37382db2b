"""A module whose connections change (vm.runtime_shape), on one fake HAL: what it sends a new
neighbour, how it checks its roles again, and bad input from the HAL."""

from __future__ import annotations

from vm_fakes import FakeHal

from vm.isa.assembler import assemble
from vm.packets import NOTIFY, PROGRAM, decode
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_shape import KEPT_PROGRAMS, kept

ROLES = RoleTable({1: "Wheel", 2: "Other"})

WHEEL = assemble("""
    CONNECTED_SIZEOF
    EQUALS_1
    IF_FALSE_GOTO done
    SET_ROLE_NOTIFY 1
done:
    MIGRATE_CONTINUE
""")
OTHER = assemble("""
    HAS_ROLE 0
    IF_FALSE_GOTO done
    SET_ROLE_NOTIFY 2
done:
    MIGRATE_CONTINUE
""")
CONTINUATION = assemble("""
    SLEEP
    HAS_ROLE 1
    IF_FALSE_GOTO done
    PUSH 1
    SET_LED_STACK
done:
    MIGRATE_CONTINUE
""")


def module(connected: set[int]) -> ModuleRuntime:
    runtime = ModuleRuntime(FakeHal(connected=set(connected)), ROLES, module_id=0)
    for code in (WHEEL, OTHER):
        runtime.inject(code)
    for _ in range(3):
        runtime.step()
    return runtime


def test_programs_are_classified_by_their_top_level_code() -> None:
    assert kept(1, WHEEL).takes_role and not kept(1, WHEEL).tests_role
    assert kept(1, OTHER).takes_role and not kept(1, OTHER).tests_role  # HAS_ROLE 0 is the guard
    assert kept(1, CONTINUATION).tests_role and not kept(1, CONTINUATION).takes_role
    assert not kept(1, b"").takes_role


def test_the_first_role_wins_and_is_checked_again_when_a_link_goes() -> None:
    runtime = module({0})
    assert runtime.role == 1 and len(runtime.kept) == 2
    runtime.hal.connected = {0, 4}
    for _ in range(4):
        runtime.step()
    assert runtime.role == 2 and runtime.rounds == 1
    runtime.hal.connected = {4}
    for _ in range(4):
        runtime.step()
    assert runtime.role == 1 and runtime.errors == []


def test_a_new_neighbour_hears_the_role_and_gets_the_programs() -> None:
    runtime = module({0})
    runtime.hal.sent.clear()
    runtime.hal.connected = {0, 4}
    runtime.step()
    on_new = [decode(packet) for ch, packet in runtime.hal.sent if ch == 4]
    kinds = [p.header.type for p in on_new]
    assert NOTIFY in kinds and kinds.count(PROGRAM) == 1  # held back: one program in flight a link
    assert all(ch in (0, 4) for ch, _ in runtime.hal.sent)


def test_connectors_a_hal_should_never_report_are_ignored() -> None:
    runtime = module({0})
    runtime.hal.connected = {0, 9, -1, 200}
    for _ in range(3):
        runtime.step()
    assert runtime.role == 1 and runtime.errors == []


def test_kept_programs_are_bounded_and_quiet() -> None:
    runtime = ModuleRuntime(FakeHal(connected={0}), ROLES, module_id=0)
    for k in range(KEPT_PROGRAMS + 8):
        runtime.inject(assemble(f"PUSH {k % 100}\nSET_LED_STACK\nEND_TERMINATE"))
        runtime.step()
    assert len(runtime.kept) == KEPT_PROGRAMS and runtime.errors == []


def _role_change(turning: bool, answer: int | None, connected: set[int]) -> ModuleRuntime:
    """A Wheel (role 1) whose joint is ``turning`` and whose last action answers ``answer``, after
    its connections became ``connected`` and its roles were checked again."""
    runtime = module({0})
    runtime.hal.turning, runtime.hal.answer = turning, answer
    runtime.hal.calls.clear()
    runtime.hal.connected = connected
    for _ in range(4):
        runtime.step()
    return runtime


def test_a_role_left_in_a_round_stops_the_joint() -> None:
    runtime = _role_change(True, 1, {0, 4})
    assert runtime.role == 2
    assert ("stop_joint", 0) in runtime.hal.calls
    assert [d for _, kind, d in runtime.event_log if kind == "joint_stopped"] == [{"role_left": "Wheel"}]


def test_a_joint_still_or_in_a_quarter_turn_is_left_alone_and_a_role_kept_keeps_it_turning() -> None:
    still = _role_change(False, 1, {0, 4})  # nothing to stop
    quarter = _role_change(True, None, {0, 4})  # a quarter turn under way finishes and answers
    kept_role = _role_change(True, 1, {4})  # one connection still: the round finds Wheel again
    assert still.role == quarter.role == 2 and kept_role.role == 1 and kept_role.rounds == 1
    for runtime in (still, quarter, kept_role):
        assert ("stop_joint", 0) not in runtime.hal.calls
        assert not any(kind == "joint_stopped" for _, kind, _ in runtime.event_log)
