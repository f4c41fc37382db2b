"""vm.observer: every callback fires with the running code and the pc of the instruction that made
the call, and a runtime without an observer (or with the do-nothing base) behaves the same."""

from __future__ import annotations

from typing import Any

from vm_fakes import FakeHal

from vm.interpreter import Outcome
from vm.isa.assembler import assemble
from vm.isa.opcodes import BY_NAME, ROTATE_DEGREES, STOP, USER_COMMAND_BASE
from vm.observer import RuntimeObserver
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "Wheel", 2: "Axle"}, {})

PROGRAM = """
    SET_ROLE_NOTIFY 1               ; 0
    HANDLE_EVENT 5 h c-h            ; 2
    INSTALL_COMMAND 1 USER_2 c e-c  ; 6
    SEND_COMMAND 1 USER_2 3         ; 11
    EVAL_COMMAND STOP 0             ; 15
    END_TERMINATE                   ; 18
h:  END_TERMINATE                   ; 19
c:  PUSH_ARGUMENT 0                 ; 20
    EVAL_COMMAND_STACK_ARG ROTATE_DEGREES
    END_TERMINATE
e:
"""
LOOP = "NOP\nl: GOTO l\nEND_TERMINATE"  # too many instructions: fails at pc 1
BAD_APPLY = "PUSH 0\nPUSH 100\nAPPLY\nEND_TERMINATE"  # command 100 is unknown: APPLY at pc 2 fails
TRACED = "ACTIVATE_DEBUG\nNOP\nEND_TERMINATE"


class Log(RuntimeObserver):
    def __init__(self) -> None:
        self.calls: list[tuple[Any, ...]] = []

    def program_stored(self, runtime: Any, slot: Any) -> None:
        self.calls.append(("program_stored", runtime, slot.code))

    def run_finished(self, runtime: Any, task: Any, result: Any) -> None:
        self.calls.append(("run_finished", runtime, task.slot.code, task.frame.pc, result.outcome))

    def role_set(self, runtime: Any, role: int, code: bytes | None, pc: int | None) -> None:
        self.calls.append(("role_set", runtime, role, code, pc))

    def handler_installed(self, runtime: Any, event: int, slot: Any, code: bytes | None,
                          pc: int | None) -> None:
        self.calls.append(("handler_installed", runtime, event, slot.code, code, pc))

    def handler_fired(self, runtime: Any, event: int, slot: Any) -> None:
        self.calls.append(("handler_fired", runtime, event, slot.code))

    def command_sent(self, runtime: Any, role: int, command: int, arg: int, code: bytes | None,
                     pc: int | None) -> None:
        self.calls.append(("command_sent", runtime, role, command, arg, code, pc))

    def command_installed(self, runtime: Any, role: int, command: int, slot: Any, code: bytes | None,
                          pc: int | None) -> None:
        self.calls.append(("command_installed", runtime, role, command, slot.code, code, pc))

    def command_executed(self, runtime: Any, command: int, arg: int, code: bytes | None,
                         pc: int | None) -> None:
        self.calls.append(("command_executed", runtime, command, arg, code, pc))

    def error(self, runtime: Any, message: str, code: bytes | None, pc: int | None) -> None:
        self.calls.append(("error", runtime, message, code, pc))

    def traced(self, runtime: Any, text: str, code: bytes | None, pc: int | None) -> None:
        self.calls.append(("traced", runtime, text, code, pc))


def scenario(observer: RuntimeObserver | None) -> ModuleRuntime:
    """One module through every kind of event: the same steps with or without an observer."""
    vm = ModuleRuntime(FakeHal(), ROLES, module_id=3)
    vm.observer = observer
    hal = vm.hal
    assert isinstance(hal, FakeHal)
    for source in (PROGRAM, None, LOOP, BAD_APPLY, TRACED):
        if source is not None:
            vm.inject(assemble(source))
        hal.sensors = {5} if source is None else set()  # the detection that fires the handler
        for _ in range(3):
            vm.step()
            hal.t += 0.01
    return vm


def test_a_runtime_has_no_observer_by_default() -> None:
    assert ModuleRuntime(FakeHal(), ROLES, module_id=0).observer is None


def test_each_callback_fires_with_the_running_code_and_the_instructions_pc() -> None:
    log = Log()
    vm = scenario(log)
    code = assemble(PROGRAM)
    handler, body = code[19:20], code[20:25]
    for pc, name in ((0, "SET_ROLE_NOTIFY"), (2, "HANDLE_EVENT"), (6, "INSTALL_COMMAND"),
                     (11, "SEND_COMMAND"), (15, "EVAL_COMMAND")):
        assert code[pc] == BY_NAME[name].opcode  # the offsets below are those instructions'
    user_2 = USER_COMMAND_BASE + 2
    assert all(call[1] is vm for call in log.calls)
    calls = [call[:1] + call[2:] for call in log.calls]
    loop, bad, traced = assemble(LOOP), assemble(BAD_APPLY), assemble(TRACED)
    assert calls == [
        ("program_stored", code),
        ("role_set", 1, code, 0),
        ("handler_installed", 5, handler, code, 2),
        ("command_installed", 1, user_2, body, code, 6),
        ("command_sent", 1, user_2, 3, code, 11),
        ("command_executed", STOP, 0, code, 15),
        ("run_finished", code, 19, Outcome.TERMINATE),
        ("command_executed", user_2, 3, None, None),  # a command task: no program runs
        ("command_executed", ROTATE_DEGREES, 3, body, 2),  # pc in the body, the code that runs
        ("run_finished", body, 5, Outcome.TERMINATE),
        ("handler_fired", 5, handler),
        ("run_finished", handler, 1, Outcome.TERMINATE),
        ("program_stored", loop),
        ("run_finished", loop, 1, Outcome.ERROR),
        ("error", vm.errors[0][1], loop, 1),  # the run's error, where it stopped
        ("program_stored", bad),
        ("error", vm.errors[1][1], bad, 2),  # the instruction's request to the module failed
        ("run_finished", bad, 4, Outcome.TERMINATE),
        ("program_stored", traced),
        ("traced", vm.event_log[-2][2]["text"], traced, 1),
        ("traced", vm.event_log[-1][2]["text"], traced, 2),
        ("run_finished", traced, 3, Outcome.TERMINATE),
    ]
    assert len(vm.errors) == 2 and "instructions in one run" in vm.errors[0][1]
    assert "unknown command 100" in vm.errors[1][1]


def test_an_observer_changes_nothing_in_the_run() -> None:
    runs = [scenario(observer) for observer in (None, RuntimeObserver(), Log())]
    seen = [(vm.event_log, vm.errors, vm.run_errors, vm.role_history, vm.stats(), vm.hal.calls, vm.hal.sent,
             [(s.code, s.kind) for s in vm.store.slots], vm.store.tasks, vm._running) for vm in runs]
    assert seen[0] == seen[1] == seen[2]
    assert seen[0][0] and seen[0][1] and seen[0][5]  # the scenario did something worth comparing
