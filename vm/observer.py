"""What a module's runtime tells an observer: the story of a run, for recordings and debuggers.

A ``RuntimeObserver`` is attached to one or more ``vm.runtime.ModuleRuntime`` objects (typed by
their base ``ModuleNode``) as their ``observer`` (None by default: then every call site costs one
``is not None`` check and the dispatch loop pays nothing). The base class does nothing; an
observer overrides what it needs.

Where a callback concerns the program running now, it gets that program's ``code`` (the bytes of
the running fragment, handler or command body) and ``pc``, the offset in ``code`` of the
instruction that made the call (``Frame.at``); both are None when nothing runs (a command task,
a received packet, a test calling the runtime directly). Callbacks run synchronously inside the
VM step: they must not change the runtime.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from vm.interpreter import Frame, Result
    from vm.runtime_node import ModuleNode
    from vm.runtime_store import Slot, Task


class RuntimeObserver:
    # opt-in for ``before_instruction``: an observer that leaves it False (a recording) costs the
    # dispatch loop nothing; the runtime reads it when a run starts
    instructions = False

    def before_instruction(self, runtime: ModuleNode, frame: Frame) -> None:
        """The instruction at ``frame.pc`` of ``frame.code`` is about to execute (only when
        ``instructions`` is True). An observer may wait here (a debugger holding the world still
        at an instruction boundary); it must not change the runtime or the frame."""

    def program_stored(self, runtime: ModuleNode, slot: Slot) -> None:
        """A program (received or injected) was accepted, stored in ``slot`` and queued."""

    def run_finished(self, runtime: ModuleNode, task: Task, result: Result) -> None:
        """A run of ``task.slot`` ended or suspended with ``result``, before the scheduler acts on it
        (so an error it reports follows this call). ``task.frame`` is the frame as the run left it."""

    def role_set(self, runtime: ModuleNode, role: int, code: bytes | None, pc: int | None) -> None:
        """SET_ROLE_NOTIFY at ``pc`` changed the module's role to ``role``."""

    def handler_installed(self, runtime: ModuleNode, event: int, slot: Slot, code: bytes | None,
                          pc: int | None) -> None:
        """HANDLE_EVENT at ``pc`` stored the handler of ``event`` in ``slot``."""

    def handler_fired(self, runtime: ModuleNode, event: int, slot: Slot) -> None:
        """A detection queued the handler of ``event`` (once per detection)."""

    def command_sent(self, runtime: ModuleNode, role: int, command: int, arg: int, code: bytes | None,
                     pc: int | None) -> None:
        """The program sends ``command`` (``arg``) to every module of ``role`` (this one included)."""

    def command_installed(self, runtime: ModuleNode, role: int, command: int, slot: Slot,
                          code: bytes | None, pc: int | None) -> None:
        """INSTALL_COMMAND at ``pc`` stored the body of user ``command`` for ``role`` in ``slot``."""

    def command_executed(self, runtime: ModuleNode, command: int, arg: int, code: bytes | None,
                         pc: int | None) -> None:
        """``command`` is executed here: a built-in drives the joint, a user command queues its body."""

    def error(self, runtime: ModuleNode, message: str, code: bytes | None, pc: int | None) -> None:
        """A runtime error: of a run (its code and failing pc), of an instruction's request to the
        module (the running code and the instruction), or of the module itself (None, None)."""

    def traced(self, runtime: ModuleNode, text: str, code: bytes | None, pc: int | None) -> None:
        """ACTIVATE_DEBUG is on: the instruction at ``pc`` is about to execute."""

    def action_started(self, runtime: ModuleNode, kind: str, arg: int, code: bytes, pc: int) -> None:
        """A connector or joint action ("connect", "disconnect", "turn") is asked of the world by the
        instruction at ``pc``; the world's answer comes as a change of the structure."""
