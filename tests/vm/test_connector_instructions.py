"""The connector and joint actions (opcodes 90..94): the run waits for the world's answer and the
instruction pushes it; the queries push at once; the verifier, the disassembler and the original
target know them."""

from __future__ import annotations

from vm_fakes import FakeHal

from vm import navigation as nav
from vm.interpreter import Frame, Outcome, run
from vm.isa.assembler import assemble
from vm.isa.disassembler import to_text
from vm.isa.opcodes import BY_NAME
from vm.isa.targets import ORIGINAL
from vm.isa.verifier import verify
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_store import Slot, Task

ROLES = RoleTable({1: "Node"}, {})


def module(connected: set[int] | None = None) -> ModuleRuntime:
    vm = ModuleRuntime(FakeHal(connected=set(connected or ())), ROLES, module_id=1)
    vm._set_frame((0, 0, 0), nav.NORTH_SOUTH, nav.IDENTITY)
    return vm


def test_opcodes_are_90_to_94_and_extensions() -> None:
    names = ["CONNECT", "DISCONNECT", "IS_CONNECTED", "IS_ALIGNED", "TURN_QUARTERS"]
    assert [BY_NAME[n].opcode for n in names] == [90, 91, 92, 93, 94]
    assert all(BY_NAME[n].ext and BY_NAME[n].pops == 1 and BY_NAME[n].pushes == 1 for n in names)


def test_queries_push_at_once() -> None:
    vm = module(connected={2})
    frame = Frame(assemble("PUSH 2\nIS_CONNECTED\nPUSH 4\nIS_CONNECTED\nPUSH 2\nIS_ALIGNED\nPUSH 9\n"
                           "IS_CONNECTED\nEND_TERMINATE"))
    assert run(frame, vm).outcome is Outcome.TERMINATE
    assert frame.stack == [1, 0, 1, 0]


def test_an_action_suspends_the_run_and_the_answer_is_pushed() -> None:
    vm = module()
    hal: FakeHal = vm.hal  # type: ignore[assignment]
    hal.answer = None
    code = assemble("PUSH 0\nCONNECT\nSET_LED_STACK\nPUSH 1\nTURN_QUARTERS\nSET_LED_STACK\nEND_TERMINATE")
    vm.store.add_and_queue(Slot(code, 1, "program"))
    vm.step()
    assert ("connect", 0) in hal.calls and vm.store.tasks and vm.store.tasks[0].wake_action
    vm.step()  # still under way
    assert vm.led == 0 and ("rotate_quarters", 1) not in hal.calls
    hal.answer = 1
    vm.step()
    assert vm.led == 1 and ("rotate_quarters", 1) in hal.calls
    hal.answer = 0
    vm.step()
    assert vm.led == 0 and not vm.store.tasks
    assert [d["action"] for _, kind, d in vm.event_log if kind == "action"] == ["connect", "turn"]


def test_verifier_disassembler_and_original_target() -> None:
    code = assemble("PUSH 0\nDISCONNECT\nIF_FALSE_GOTO end\nend: END_TERMINATE")
    assert verify(code) == []
    assert "DISCONNECT" in to_text(code)
    assert any("DISCONNECT" in e or "91" in e for e in verify(code, target=ORIGINAL))
    assert verify(assemble("CONNECT\nEND_TERMINATE"))  # pops an empty stack
    assert isinstance(Task(None).wake_action, bool)
