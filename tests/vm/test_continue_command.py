"""CONTINUE_COMMAND (issue 25): a run goes on in the code of a user command, with the same stack
and argument; a command installed for any role runs on a module that has no role too."""

from __future__ import annotations

from vm_fakes import FakeHal

from vm.isa.assembler import assemble
from vm.isa.verifier import verify
from vm.roles import ANY_ROLE, NO_ROLE, RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "A", 2: "B"}, {})
# installs for any role: show the run's argument + 5
INSTALL = """
    INSTALL_COMMAND 255 USER_2 c e-c
    END_TERMINATE
c:  PUSH_ARGUMENT 0
    PUSH 5
    ADD
    SET_LED_STACK
    END_TERMINATE
e:
"""


def module() -> ModuleRuntime:
    vm = ModuleRuntime(FakeHal(connected={0, 1}), ROLES, module_id=3)
    vm.inject(assemble("END_TERMINATE"))  # the frame
    vm.step()
    return vm


def test_installed_for_any_role_means_every_role_and_none() -> None:
    assert ROLES.roles_instance_of(ANY_ROLE) == [NO_ROLE, 1, 2]
    assert ROLES.roles_instance_of(1) == [1]


def test_the_run_goes_on_in_the_command_on_a_module_without_role() -> None:
    vm = module()
    vm.inject(assemble(INSTALL))
    vm.step()
    vm.inject(assemble("SET_LED 1\nCONTINUE_COMMAND USER_2"))
    vm.step()
    assert vm.role == 0 and vm.led == 5 and not vm.errors  # argument 0 + 5, in the same step


def test_and_with_a_role() -> None:
    vm = module()
    vm.inject(assemble(INSTALL))
    vm.step()
    vm.inject(assemble("SET_ROLE_NOTIFY 2\nCONTINUE_COMMAND USER_2"))
    vm.step()
    assert vm.role == 2 and vm.led == 5 and not vm.errors


def test_no_code_for_the_command_is_a_runtime_error_not_a_crash() -> None:
    vm = module()
    vm.inject(assemble("CONTINUE_COMMAND USER_3"))
    vm.step()
    assert any("no code for command 131" in message for _, message in vm.errors)


def test_the_verifier_knows_control_does_not_fall_through() -> None:
    assert verify(assemble("PUSH 1\nCONTINUE_COMMAND USER_0")) == []
