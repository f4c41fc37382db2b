"""ACT (issue 24, opcode 95): the action of a compact sequence step from its one-byte code —
disconnect, connect or a quarter turn, waiting for the answer like those — and 0 at once, with no
action, for every other value (any byte a module whose step it is not may hold). An extension."""

from __future__ import annotations

import pytest
from vm_fakes import FakeHal

from rdcd_core.frontend import check_text
from vm import navigation as nav
from vm.interpreter import Frame, Outcome, run
from vm.isa.assembler import assemble
from vm.isa.opcodes import BY_NAME, step_action
from vm.isa.targets import ORIGINAL
from vm.isa.verifier import verify
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "Node"}, {})
CODES = {1: ("disconnect", 0), 2: ("disconnect", 2), 3: ("disconnect", 4), 4: ("disconnect", 6),
         5: ("connect", 0), 6: ("connect", 2), 7: ("connect", 4), 8: ("connect", 6),
         9: ("turn", -2), 10: ("turn", -1), 12: ("turn", 1), 13: ("turn", 2)}
HAL_CALL = {"disconnect": "disconnect", "connect": "connect", "turn": "rotate_quarters"}


def module() -> ModuleRuntime:
    vm = ModuleRuntime(FakeHal(connected=set()), ROLES, module_id=1)
    vm._set_frame((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY)
    return vm


def test_the_instruction_and_its_codes() -> None:
    ins = BY_NAME["ACT"]
    assert (ins.opcode, ins.pops, ins.pushes, ins.ext, ins.size) == (95, 1, 1, True, 1)
    assert {a: step_action(a) for a in range(-128, 128) if step_action(a) is not None} == CODES


@pytest.mark.parametrize("code", sorted(CODES))
def test_a_step_code_acts_and_the_run_waits_for_the_answer(code: int) -> None:
    vm = module()
    hal: FakeHal = vm.hal  # type: ignore[assignment]
    hal.answer = None
    frame = Frame(assemble(f"PUSHC {code}\nACT\nSET_LED_STACK\nEND_TERMINATE"))
    assert run(frame, vm).outcome is Outcome.ACTION
    kind, arg = CODES[code]
    assert hal.calls[-1] == (HAL_CALL[kind], arg)


@pytest.mark.parametrize("code", [0, 11, 14, -1, -14, 127, -128])
def test_any_other_value_answers_zero_at_once_and_does_nothing(code: int) -> None:
    vm = module()
    hal: FakeHal = vm.hal  # type: ignore[assignment]
    frame = Frame(assemble(f"PUSHC {code}\nACT\nEND_TERMINATE"))
    assert run(frame, vm).outcome is Outcome.TERMINATE
    assert frame.stack == [0] and not [c for c in hal.calls if c[0] in HAL_CALL.values()]


def test_verifier_and_original_target() -> None:
    code = assemble("PUSH 5\nACT\nIF_FALSE_GOTO end\nend: END_TERMINATE")
    assert verify(code) == []
    assert verify(code, target=ORIGINAL)  # not on the firmware
    assert verify(assemble("ACT\nEND_TERMINATE"))  # pops an empty stack


def test_self_act_is_an_action_where_actions_may_stand() -> None:
    base = "state s := 0;\nrole A {{ self.x() >= 0; behavior b() {{ {} }} }}\ndeployment {{ A }}\n"
    ok = check_text(base.format("if (self.act(s)) { s := 0; }"))
    assert [d for d in ok.diagnostics if d.severity.name == "ERROR"] == []
    bad = check_text(base.format("s := s + 1; if (self.act(s) == true) { s := 0; }"))
    assert "E320" in {d.code for d in bad.diagnostics}
    wrong = check_text(base.format("if (self.act(EAST)) { s := 0; }"))
    assert any(d.severity.name == "ERROR" for d in wrong.diagnostics)
