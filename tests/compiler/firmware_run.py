"""Runs compiled code as the original firmware would (docs/vm.md), for the lowering tests: this
project's interpreter for every instruction the firmware runs the same way, and, in front of it,
what the firmware does differently with the instructions compiled code uses: an unimplemented
opcode halts the module, CONNECTED_DIR_SIZEOF reads the bits set *in the count* and halts on the
axes and directions it does not support, the stack holds 5 values, a run ends after 100
instructions. (The VM profile ``original`` is the full model; this is the part a single run of
discovery or startup code meets.)"""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core.compiler.geometry import facing
from vm import interpreter
from vm.interpreter import Frame, Outcome
from vm.isa.disassembler import decode_at
from vm.isa.targets import DEFAULT, ORIGINAL, Target


@dataclass
class Module:
    """A module in a fixed local state that records what the code asks of it."""

    axis: int
    connected: int  # virtual channels with a neighbour
    position: tuple[int, int, int] = (0, 0, 0)
    roles: list[int] = field(default_factory=list)
    leds: list[int] = field(default_factory=list)
    commands: list[tuple[int, int]] = field(default_factory=list)

    def axis_code(self) -> int:
        return self.axis

    def coords(self) -> tuple[int, int, int]:
        return self.position

    def connected_virtual(self) -> int:
        return self.connected

    def facing(self, direction: int) -> int:
        return facing(self.axis, direction)

    def has_role(self, role: int) -> bool:
        return bool(self.roles) and self.roles[-1] == role

    def connected_role(self, direction: int, role: int) -> int:
        return 0

    def set_role_notify(self, role: int) -> None:
        self.roles.append(role)

    def set_led(self, value: int) -> None:
        self.leds.append(value)

    def eval_command(self, command: int, arg: int) -> None:
        self.commands.append((command, arg))

    def __getattr__(self, name: str):  # every other request: nothing to record
        return lambda *args: 0


SUSPENDS = ("sleep", "sleep_rotations")  # the run goes on after the wait, with its frame


def run(code: bytes, module: Module, target: Target) -> str:
    """Runs ``code`` on ``module`` until it ends (resuming after SLEEP); returns how it ended
    ("terminate", "migrate", ..., or "halt: why")."""
    frame = Frame(code)
    while True:
        ended = _run_once(frame, module, target)
        if ended not in SUSPENDS:
            return ended


def _run_once(frame: Frame, module: Module, target: Target) -> str:
    code = frame.code
    for _ in range(target.max_steps_per_run):
        if not 0 <= frame.pc < len(code):
            return "halt: control left the program"
        d = decode_at(code, frame.pc)
        if d.info is not None and not target.implements(d.opcode):
            return f"halt: unknown instruction {d.name}"
        if d.name == "CONNECTED_DIR_SIZEOF" and target is ORIGINAL:
            direction = d.operands[0]
            if not target.dir_sizeof_runs(module.axis, direction):
                return f"halt: CONNECTED_DIR_SIZEOF {direction} on axis {module.axis}"
            count = (module.connected & module.facing(direction)).bit_count()
            frame.stack.append(count.bit_count())
            frame.pc += d.size
        else:
            result = interpreter._step(frame, module)  # noqa: SLF001 - one instruction at a time
            if result is not None:
                return result.outcome.value
        if len(frame.stack) > target.max_stack:
            return "halt: stack overflow"
    return "halt: too many instructions"


def run_default(code: bytes, module: Module) -> str:
    frame = Frame(code)
    while True:
        result = interpreter.run(frame, module)
        if result.outcome is Outcome.ERROR:
            return f"halt: {result.message}"
        if result.outcome.value not in SUSPENDS:
            return result.outcome.value


__all__ = ["DEFAULT", "ORIGINAL", "Module", "run", "run_default"]
