"""The DCD-VM dispatch loop: runs one program (a ``Frame``) against a ``Machine`` (the module).

A run ends with an ``Outcome``: terminate, repeat, migrate, sleep (one second), sleep for joint
turns, or a runtime error (stack under/overflow, more than 255 instructions, bad operand). A
suspended frame keeps its pc and stack and is resumed by the runtime. Values are signed bytes.
The interpreter never raises for any code: unverified bytes end in an error outcome.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import Protocol

from vm.isa.opcodes import BY_OPCODE, MAX_STACK, MAX_STEPS_PER_RUN, PUSH_SMALL_BASE
from vm.navigation import DIRECTIONS, DOWN, EAST, EAST_WEST, NORTH, NORTH_SOUTH, SOUTH, UP, UP_DOWN, WEST


def s8(value: int) -> int:
    """Wrap to a signed byte."""
    return ((value + 128) & 0xFF) - 128


class Outcome(Enum):
    TERMINATE = "terminate"
    REPEAT = "repeat"
    MIGRATE = "migrate"
    SLEEP = "sleep"
    SLEEP_ROTATIONS = "sleep_rotations"
    ERROR = "error"


@dataclass
class Frame:
    code: bytes
    arg: int = 0
    pc: int = 0
    stack: list[int] = field(default_factory=list)
    debug: bool = False


@dataclass(frozen=True)
class Result:
    outcome: Outcome
    turns: int = 0  # SLEEP_ROTATIONS: full joint turns to wait
    message: str = ""  # ERROR: what went wrong


class Machine(Protocol):
    """What a program may ask of its module (implemented by ``vm.runtime.ModuleRuntime``)."""

    def axis_code(self) -> int: ...
    def coords(self) -> tuple[int, int, int]: ...
    def connected_virtual(self) -> int: ...
    def facing(self, direction: int) -> int: ...
    def has_role(self, role: int) -> bool: ...
    def connected_role(self, direction: int, role: int) -> int: ...
    def set_role_notify(self, role: int) -> None: ...
    def handle_event(self, event: int, code: bytes) -> None: ...
    def clear_event(self, event: int) -> None: ...
    def enable_event(self, event: int, enabled: bool) -> None: ...
    def send_command(self, role: int, command: int, arg: int) -> None: ...
    def eval_command(self, command: int, arg: int) -> None: ...
    def install_command(self, role: int, command: int, code: bytes) -> None: ...
    def clear_command_queue(self, command: int) -> None: ...
    def set_led(self, value: int) -> None: ...
    def trace(self, frame: Frame, text: str) -> None: ...


class VMError(Exception):
    """A runtime error of the running program (caught by ``run``, reported by the runtime)."""


_ROLE_DIRS = {36: DOWN, 37: UP, 38: EAST, 39: WEST, 40: NORTH, 41: SOUTH}
_AXIS_OPS = {1: EAST_WEST, 2: NORTH_SOUTH, 3: UP_DOWN}
_COMPARE = {22: lambda a, b: a > b, 23: lambda a, b: a < b, 56: lambda a, b: a == b}
_ARITH = {57: lambda a, b: a + b, 58: lambda a, b: a - b}
_COORD_CMP = {24: (0, True), 25: (0, False), 26: (1, True), 27: (1, False), 28: (2, True), 29: (2, False)}
_ENDINGS = {13: Outcome.TERMINATE, 14: Outcome.REPEAT, 18: Outcome.MIGRATE}


def run(frame: Frame, m: Machine) -> Result:
    """Run ``frame`` until it ends or suspends, at most 255 instructions."""
    try:
        for _ in range(MAX_STEPS_PER_RUN):
            result = _step(frame, m)
            if result is not None:
                return result
        return Result(Outcome.ERROR, message=f"more than {MAX_STEPS_PER_RUN} instructions in one run")
    except VMError as e:
        return Result(Outcome.ERROR, message=f"pc {frame.pc}: {e}")


def _push(frame: Frame, value: int) -> None:
    if len(frame.stack) >= MAX_STACK:
        raise VMError("stack overflow")
    frame.stack.append(s8(value))


def _pop(frame: Frame) -> int:
    if not frame.stack:
        raise VMError("stack underflow")
    return frame.stack.pop()


def _fetch(frame: Frame) -> tuple[int, tuple[int, ...]]:
    code, pc = frame.code, frame.pc
    if not 0 <= pc < len(code):
        raise VMError(f"control left the {len(code)}-byte program")
    op = code[pc]
    if op >= PUSH_SMALL_BASE:
        frame.pc = pc + 1
        return op, ()
    ins = BY_OPCODE.get(op)
    if ins is None:
        raise VMError(f"unknown opcode {op}")
    if pc + ins.size > len(code):
        raise VMError(f"{ins.name} is missing operands")
    frame.pc = pc + ins.size
    return op, tuple(code[pc + 1: pc + ins.size])


def _embedded(frame: Frame, start: int, size: int) -> bytes:
    if size == 0 or start + size > len(frame.code):
        raise VMError(f"code range [{start}, {start + size}) outside the program")
    return frame.code[start: start + size]


def _direction(d: int) -> int:
    if d not in DIRECTIONS:
        raise VMError(f"bad direction {d}")
    return d


def _step(frame: Frame, m: Machine) -> Result | None:  # noqa: C901 - one dispatch table
    at = frame.pc
    op, a = _fetch(frame)
    if frame.debug:
        m.trace(frame, f"{at}: {BY_OPCODE[op].name if op < 128 else 'PUSH'} {list(a)} stack={frame.stack}")
    if op >= PUSH_SMALL_BASE:
        _push(frame, op - PUSH_SMALL_BASE)
    elif op in _AXIS_OPS:
        _push(frame, int(m.axis_code() == _AXIS_OPS[op]))
    elif op == 4:
        _push(frame, m.connected_virtual())
    elif op == 5:
        _push(frame, m.connected_virtual().bit_count())
    elif 6 <= op <= 10:
        _push(frame, int(_pop(frame) == op - 6))
    elif op == 11:
        _push(frame, m.connected_virtual() & m.facing(_direction(a[0])))
    elif op == 12:
        _push(frame, (m.connected_virtual() & m.facing(_direction(a[0]))).bit_count())
    elif op in _ENDINGS:
        return Result(_ENDINGS[op])
    elif op in (15, 47):
        if (_pop(frame) != 0) == (op == 47):
            frame.pc = a[0]
    elif op == 16:
        frame.pc = a[0]
    elif op == 17:
        m.set_role_notify(a[0])
    elif 19 <= op <= 21:
        _push(frame, m.coords()[op - 19])
    elif op in _COMPARE:
        b = _pop(frame)
        _push(frame, int(_COMPARE[op](_pop(frame), b)))
    elif op in _ARITH:
        b = _pop(frame)
        _push(frame, _ARITH[op](_pop(frame), b))
    elif op in _COORD_CMP:
        axis, greater = _COORD_CMP[op]
        value, coord = _pop(frame), m.coords()[axis]
        _push(frame, int(coord > value if greater else coord < value))
    elif op == 30:
        if a[0] > 7:
            raise VMError(f"bad event {a[0]}")
        m.handle_event(a[0], _embedded(frame, a[1], a[2]))
    elif op == 31:
        m.send_command(a[0], a[1], s8(a[2]))
    elif op == 32:
        m.clear_event(a[0])
    elif op == 33:
        m.eval_command(a[0], s8(a[1]))
    elif op == 34:
        _push(frame, int(m.has_role(a[0])))
    elif op == 35:
        _push(frame, m.connected_role(_direction(a[0]), a[1]))
    elif op in _ROLE_DIRS:
        _push(frame, int(m.connected_role(_ROLE_DIRS[op], a[0]) != 0))
    elif op == 42:
        m.install_command(a[0], a[1], _embedded(frame, a[2], a[3]))
    elif op == 43:
        return Result(Outcome.SLEEP)
    elif op in (44, 45):
        m.enable_event(a[0], op == 45)
    elif op == 46:
        m.clear_command_queue(a[0])
    elif op == 48:
        return Result(Outcome.SLEEP_ROTATIONS, turns=s8(a[0]))
    elif op == 49:
        _push(frame, (_pop(frame) & 0xFF).bit_count())
    elif op == 50:
        _push(frame, -_pop(frame))
    elif op == 51:
        frame.debug = True
    elif op == 52:
        f = _pop(frame)
        arg = _pop(frame)
        m.eval_command(f & 0xFF, arg)
        _push(frame, 0)
    elif op == 53:
        _push(frame, frame.arg)
    elif op == 54:
        _push(frame, s8(a[0]))
    elif op == 55:
        m.set_led(s8(a[0]))
    elif op == 59:
        m.send_command(a[0], a[1], _pop(frame))
    elif op == 60:
        m.eval_command(a[0], _pop(frame))
    # 127 NOP: nothing
    return None
