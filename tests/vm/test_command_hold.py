"""Commands that arrive before their code or before the module's role are held (default target)
until the code is installed, bounded in number and time (vm/runtime_hold.py, docs/vm.md)."""

from __future__ import annotations

from vm_fakes import FakeHal

from vm import navigation as nav
from vm.isa.assembler import assemble
from vm.isa.targets import ORIGINAL
from vm.packets import COMMAND, CommandPacket, encode, make_header
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_hold import HOLD_S, MAX_HELD

ROLES = RoleTable({1: "Wheel", 2: "LeftWheel", 3: "Axle"}, {2: frozenset({1, 2})})
INSTALL = """
    INSTALL_COMMAND 1 USER_0 c e-c
    END_TERMINATE
c:  PUSH_ARGUMENT 0
    EVAL_COMMAND_STACK_ARG ROTATE_DEGREES
    END_TERMINATE
e:
"""


def module(**kwargs) -> ModuleRuntime:
    vm = ModuleRuntime(FakeHal(connected={0, 1}), ROLES, module_id=3, **kwargs)
    vm.inject(assemble("END_TERMINATE"))  # the frame
    vm.step()
    return vm


def command(ident: int, role: int = 1, arg: int = 3) -> bytes:
    return encode(CommandPacket(make_header(COMMAND, ident, *nav.receiver(0, 0, 0, 2, 1)), role, 128, arg))


def advance(vm: ModuleRuntime, seconds: float, dt: float = 0.05) -> None:
    for _ in range(round(seconds / dt)):
        vm.step()
        vm.hal.t += dt


def test_a_command_before_its_code_runs_once_the_code_is_installed() -> None:
    vm = module()
    vm.inject(assemble("SET_ROLE_NOTIFY 1\nEND_TERMINATE"))
    advance(vm, 0.1)
    vm.receive(1, command(9))
    advance(vm, 1.0)
    assert vm.hal.calls == [] and len(vm.held.items) == 1
    vm.inject(assemble(INSTALL))
    advance(vm, 0.3)
    assert vm.hal.calls == [("rotate_by", 30.0)] and not vm.held and not vm.errors


def test_a_command_before_the_role_runs_when_the_module_takes_it() -> None:
    vm = module()
    vm.receive(1, command(9, role=1))
    advance(vm, 0.5)
    vm.inject(assemble(INSTALL))  # code for Wheel, module has no role yet
    advance(vm, 0.5)
    assert vm.hal.calls == []
    vm.inject(assemble("SET_ROLE_NOTIFY 2\nEND_TERMINATE"))  # LeftWheel is a Wheel
    advance(vm, 0.3)
    assert vm.hal.calls == [("rotate_by", 30.0)]


def test_a_command_for_another_role_is_forgotten_silently() -> None:
    vm = module()
    vm.receive(1, command(9, role=1))
    advance(vm, 0.2)
    vm.inject(assemble("SET_ROLE_NOTIFY 3\nEND_TERMINATE"))  # an Axle
    advance(vm, HOLD_S + 1)
    assert not vm.held and vm.hal.calls == [] and vm.errors == []


def test_code_that_never_comes_is_reported_after_the_hold_time() -> None:
    vm = module()
    vm.inject(assemble("SET_ROLE_NOTIFY 1\nEND_TERMINATE"))
    vm.receive(1, command(9, arg=-5))
    advance(vm, HOLD_S + 1)
    assert not vm.held
    assert [m for _, m in vm.errors] == [f"user command 0 (argument -5) dropped: its code did not "
                                         f"arrive within {HOLD_S:g} s"]


def test_the_hold_is_bounded() -> None:
    vm = module()
    vm.inject(assemble("SET_ROLE_NOTIFY 1\nEND_TERMINATE"))
    advance(vm, 0.1)
    for ident in range(MAX_HELD + 2):
        vm.receive(1, command(ident + 1, arg=ident))
    advance(vm, 0.2)
    assert len(vm.held.items) == MAX_HELD
    assert sum("wait for their code already" in m for _, m in vm.errors) == 2


def test_the_original_firmware_drops_it() -> None:
    vm = module(target=ORIGINAL)
    vm.receive(1, command(9))
    advance(vm, 0.5)
    assert not vm.held and not vm._holds
