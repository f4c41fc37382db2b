"""The DCD-VM dispatch loop: runs one program (a ``Frame``) against a ``Machine`` (the module).

A run ends with an ``Outcome``: terminate, repeat, migrate, sleep (one second), sleep for joint
turns, a runtime error (stack under/overflow, too many instructions, bad operand), or a halt of the
whole module (the firmware's reaction to an instruction it does not execute). A suspended frame
keeps its pc and stack and is resumed by the runtime. Values are signed bytes. The interpreter
never raises for any code: unverified bytes end in an error outcome.

The ``Target`` (vm.isa.targets) is the VM profile: which opcodes execute, the stack depth, the
instructions per run and the firmware's quirks in what an instruction does (docs/vm.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from typing import Protocol

from vm.isa.opcodes import (
    ACTIONS,
    ANGLE_STEP,
    BY_OPCODE,
    PUSH_SMALL_BASE,
    ROTATE_CCW,
    ROTATE_CW,
    ROTATE_DEGREES,
    ROTATE_TO,
    SPEEDS,
    STATE_SLOTS,
    STOP,
    TURNS,
    divided,
    remainder,
    saturated,
    signed_byte,
    step_action,
)
from vm.isa.targets import DEFAULT, Target
from vm.navigation import AXES, AXIS_NAMES, DIRECTION_NAMES, DIRECTIONS
from vm.roles import ANY_ROLE


class Outcome(Enum):
    TERMINATE = "terminate"
    REPEAT = "repeat"
    MIGRATE = "migrate"
    SLEEP = "sleep"
    SLEEP_ROTATIONS = "sleep_rotations"
    ERROR = "error"
    HALT = "halt"  # the module stops (firmware profile): nothing runs or is received any more
    WAIT = "wait"  # END_WAIT: run again when a value of the module changes
    ACTION = "action"  # CONNECT, DISCONNECT, TURN_QUARTERS: resume, with the result pushed, when done


@dataclass
class Frame:
    code: bytes
    arg: int = 0
    pc: int = 0
    stack: list[int] = field(default_factory=list)
    debug: bool = False
    # offset of the instruction that is asking the module something now (``vm.observer``): set
    # by the few instructions that call the module with an effect, so the dispatch loop pays nothing
    at: int = 0


@dataclass(frozen=True)
class Result:
    outcome: Outcome
    turns: int = 0  # SLEEP_ROTATIONS: full joint turns to wait
    message: str = ""  # ERROR, HALT: what went wrong
    pc: int | None = None  # ERROR, HALT: offset of the failing instruction in the running code


class Machine(Protocol):
    """What a program may ask of its module (implemented by ``vm.runtime.ModuleRuntime``)."""

    def axis_code(self) -> int: ...
    def coords(self) -> tuple[int, int, int]: ...
    def connected_virtual(self) -> int: ...
    def connected_physical(self) -> int: ...
    def facing(self, direction: int) -> int: ...
    def has_role(self, role: int) -> bool: ...
    def connected_role(self, direction: int, role: int) -> int: ...
    def set_role_notify(self, role: int) -> bool | None: ...
    def handle_event(self, event: int, code: bytes) -> None: ...
    def clear_event(self, event: int) -> None: ...
    def enable_event(self, event: int, enabled: bool) -> None: ...
    def send_command(self, role: int, command: int, arg: int) -> None: ...
    def eval_command(self, command: int, arg: int) -> None: ...
    def install_command(self, role: int, command: int, code: bytes) -> None: ...
    def clear_command_queue(self, command: int) -> None: ...
    def set_led(self, value: int) -> None: ...
    def load_state(self, index: int) -> int: ...
    def store_state(self, index: int, value: int) -> None: ...
    def neighbour_values(self, gather: int, where: int) -> int: ...
    def run_local(self, code: bytes) -> None: ...
    def command_code(self, command: int) -> bytes | None: ...
    def load_data(self) -> int: ...
    def store_data(self, value: int) -> None: ...
    def start_action(self, kind: str, arg: int, code: bytes, pc: int) -> None: ...
    def is_connected(self, connector: int) -> bool: ...
    def is_aligned(self, connector: int) -> bool: ...
    def trace(self, frame: Frame, text: str) -> None: ...


class VMError(Exception):
    """A runtime error of the running program (caught by ``run``, reported by the runtime)."""

    def __init__(self, message: str, *, halts: bool = False) -> None:
        super().__init__(message)
        self.halts = halts  # the firmware stops the module instead of ending the run


_ROLE_DIRS = {f"CONNECTED_{DIRECTION_NAMES[d]}_ROLE": d for d in DIRECTIONS}
_AXIS_OPS = {f"CENTER_POSITION_{AXIS_NAMES[a]}": a for a in AXES}
_EQUALS = {f"EQUALS_{k}": k for k in range(5)}
_COORDS = {"COORD_X": 0, "COORD_Y": 1, "COORD_Z": 2}
_COMPARE = {"GREATER": lambda a, b: a > b, "LESSER": lambda a, b: a < b, "EQUALS": lambda a, b: a == b}
_ARITH = {"ADD": lambda a, b: saturated(a + b), "SUB": lambda a, b: saturated(a - b),
          "MUL": lambda a, b: saturated(a * b), "MIN": min, "MAX": max}
_DIVIDE = {"DIV": divided, "MOD": remainder}
_COORD_CMP = {f"COORD_{c}_{cmp}": (i, cmp == "GREATER") for i, c in enumerate("XYZ")
              for cmp in ("GREATER", "LESSER")}
_ENDINGS = {"END_TERMINATE": Outcome.TERMINATE, "END_REPEAT": Outcome.REPEAT,
            "MIGRATE_CONTINUE": Outcome.MIGRATE, "END_WAIT": Outcome.WAIT}


def run(frame: Frame, m: Machine, target: Target = DEFAULT,
        before: Callable[[Frame], None] | None = None) -> Result:
    """Run ``frame`` until it ends or suspends, at most ``target.max_steps_per_run`` instructions.
    ``before`` (a ``vm.observer`` hook, None by default) is called before each instruction; the
    loop without it is kept separate so that it pays nothing."""
    at = frame.pc
    try:
        if before is None:
            for _ in range(target.max_steps_per_run):
                at = frame.pc
                result = _step(frame, m, target)
                if result is not None:
                    return result
        else:
            for _ in range(target.max_steps_per_run):
                at = frame.pc
                before(frame)
                result = _step(frame, m, target)
                if result is not None:
                    return result
        return Result(Outcome.ERROR, message=f"more than {target.max_steps_per_run} instructions in one run",
                      pc=frame.pc)
    except VMError as e:
        return Result(Outcome.HALT if e.halts else Outcome.ERROR, message=f"pc {at}: {e}", pc=at)


def _push(frame: Frame, value: int, target: Target) -> None:
    if len(frame.stack) >= target.max_stack:
        raise VMError("stack overflow")
    frame.stack.append(signed_byte(value))


def _pop(frame: Frame) -> int:
    if not frame.stack:
        raise VMError("stack underflow")
    return frame.stack.pop()


def _fetch(frame: Frame, target: Target) -> tuple[str, int, tuple[int, ...]]:
    """(name, opcode, operands) of the instruction at pc; advances pc. A push is named PUSH."""
    code, pc = frame.code, frame.pc
    if not 0 <= pc < len(code):
        raise VMError(f"control left the {len(code)}-byte program")
    op = code[pc]
    if op >= PUSH_SMALL_BASE:
        frame.pc = pc + 1
        return "PUSH", op, ()
    ins = BY_OPCODE.get(op)
    if not target.implements(op):
        name = f" ({ins.name})" if ins else ""
        raise VMError(f"unknown instruction {op}{name}", halts=target.quirks.unknown_instruction_halts)
    if ins is None:
        raise VMError(f"unknown opcode {op}")
    if pc + ins.size > len(code):
        raise VMError(f"{ins.name} is missing operands")
    frame.pc = pc + ins.size
    return ins.name, op, tuple(code[pc + 1: pc + ins.size])


def _embedded(frame: Frame, start: int, size: int) -> bytes:
    if size == 0 or start + size > len(frame.code):
        raise VMError(f"code range [{start}, {start + size}) outside the program")
    return frame.code[start: start + size]


def _state(index: int) -> int:
    if index >= STATE_SLOTS:
        raise VMError(f"state {index} is outside the module's {STATE_SLOTS} state bytes")
    return index


def _direction(d: int) -> int:
    if d not in DIRECTIONS:
        raise VMError(f"bad direction {d}")
    return d


def _connected(m: Machine, target: Target) -> int:
    """CONNECTED: virtual channels; the firmware sets bit p+1 for physical channel p (7 is lost)."""
    if target.quirks.connected_physical_bits:
        return (m.connected_physical() << 1) & 0xFF
    return m.connected_virtual()


def _connected_dir_sizeof(m: Machine, d: int, target: Target) -> int:
    """The number of connected channels facing d; the firmware pushes the bits set *in that count*
    and knows only some axis/direction pairs (the others halt it)."""
    q = target.quirks
    if q.connected_dir_sizeof_limited and not target.dir_sizeof_runs(m.axis_code(), d):
        axis = AXIS_NAMES.get(m.axis_code(), "unknown")
        raise VMError(f"CONNECTED_DIR_SIZEOF {DIRECTION_NAMES[d]} is not supported on a {axis} module",
                      halts=q.unknown_instruction_halts)
    count = (m.connected_virtual() & m.facing(d)).bit_count()
    return count.bit_count() if q.connected_dir_sizeof_popcount_of_count else count


_JOINT_STACK = frozenset({"TURN_STACK", "TURN_TO_STACK", "TURN_BY_STACK", "SLEEP_ROTATIONS_STACK"})


def _joint_stack(name: str, v: int, m: Machine) -> Result | None:
    """The joint instructions that take their value from the stack (issue 25): the value in the
    program's units, checked as the checker checks a constant; out of range is a runtime error
    that names it (the run ends, the module goes on)."""
    if name == "TURN_STACK":
        if not SPEEDS[0] <= v <= SPEEDS[1]:
            raise VMError(f"turnContinuously: speed {v} is outside {SPEEDS[0]}..{SPEEDS[1]}")
        m.eval_command(ROTATE_CW if v > 0 else ROTATE_CCW if v < 0 else STOP, abs(v))
    elif name == "SLEEP_ROTATIONS_STACK":
        if not TURNS[0] <= v <= TURNS[1]:
            raise VMError(f"sleepWhileTurning: {v} turns is outside {TURNS[0]}..{TURNS[1]}")
        return Result(Outcome.SLEEP_ROTATIONS, turns=v)
    else:
        what = "turnTowards" if name == "TURN_TO_STACK" else "turnDegrees"
        if v % ANGLE_STEP:
            raise VMError(f"{what}: {v} degrees is not a multiple of {ANGLE_STEP}")
        m.eval_command(ROTATE_TO if name == "TURN_TO_STACK" else ROTATE_DEGREES, v // ANGLE_STEP)
    return None


def _step(frame: Frame, m: Machine, target: Target = DEFAULT) -> Result | None:  # noqa: C901 - one dispatch table
    at = frame.pc
    name, op, a = _fetch(frame, target)
    if frame.debug:
        frame.at = at
        m.trace(frame, f"{at}: {name} {list(a)} stack={frame.stack}")
    if name == "PUSH":
        _push(frame, op - PUSH_SMALL_BASE, target)
    elif name in _AXIS_OPS:
        _push(frame, int(m.axis_code() == _AXIS_OPS[name]), target)
    elif name == "CONNECTED":
        _push(frame, _connected(m, target), target)
    elif name == "CONNECTED_SIZEOF":
        _push(frame, m.connected_virtual().bit_count(), target)
    elif name in _EQUALS:
        _push(frame, int(_pop(frame) == _EQUALS[name]), target)
    elif name == "CONNECTED_DIR":
        _push(frame, m.connected_virtual() & m.facing(_direction(a[0])), target)
    elif name == "CONNECTED_DIR_SIZEOF":
        _push(frame, _connected_dir_sizeof(m, _direction(a[0]), target), target)
    elif name in _ENDINGS:
        return Result(_ENDINGS[name])
    elif name in ("IF_FALSE_GOTO", "IF_TRUE_GOTO"):
        if (_pop(frame) != 0) == (name == "IF_TRUE_GOTO"):
            frame.pc = a[0]
    elif name == "GOTO":
        frame.pc = a[0]
    elif name == "SET_ROLE_NOTIFY":
        frame.at = at
        if m.set_role_notify(a[0]) is False:  # a re-check that found the role kept (vm.runtime_shape)
            return Result(Outcome.TERMINATE)
    elif name in _COORDS:
        _push(frame, m.coords()[_COORDS[name]], target)
    elif name in _COMPARE:
        b = _pop(frame)
        _push(frame, int(_COMPARE[name](_pop(frame), b)), target)
    elif name in _ARITH:
        b = _pop(frame)
        _push(frame, _ARITH[name](_pop(frame), b), target)
    elif name in _DIVIDE:
        b = _pop(frame)
        a = _pop(frame)
        if b == 0:
            raise VMError(f"division by zero: {a} {'/' if name == 'DIV' else '%'} 0")
        _push(frame, _DIVIDE[name](a, b), target)
    elif name in _JOINT_STACK:
        frame.at = at
        result = _joint_stack(name, _pop(frame), m)
        if result is not None:
            return result
    elif name in _COORD_CMP:
        axis, greater = _COORD_CMP[name]
        value, coord = _pop(frame), m.coords()[axis]
        _push(frame, int(coord > value if greater else coord < value), target)
    elif name == "HANDLE_EVENT":
        if a[0] > 7:
            raise VMError(f"bad event {a[0]}")
        frame.at = at
        m.handle_event(a[0], _embedded(frame, a[1], a[2]))
    elif name == "SEND_COMMAND":
        frame.at = at
        m.send_command(a[0], a[1], signed_byte(a[2]))
    elif name == "CLEAR_EVENT":
        m.clear_event(a[0])
    elif name == "EVAL_COMMAND":
        frame.at = at
        m.eval_command(a[0], signed_byte(a[1]))
    elif name == "HAS_ROLE":
        _push(frame, int(m.has_role(a[0])), target)
    elif name == "CONNECTED_ROLE":
        _push(frame, m.connected_role(_direction(a[0]), a[1]), target)
    elif name in _ROLE_DIRS:
        _push(frame, int(m.connected_role(_ROLE_DIRS[name], a[0]) != 0), target)
    elif name == "INSTALL_COMMAND":
        frame.at = at
        m.install_command(a[0], a[1], _embedded(frame, a[2], a[3]))
    elif name == "SLEEP":
        return Result(Outcome.SLEEP)
    elif name in ("DISABLE_EVENT", "ENABLE_EVENT"):
        m.enable_event(a[0], name == "ENABLE_EVENT")
    elif name == "CLEAR_COMMAND_QUEUE":
        m.clear_command_queue(a[0])
    elif name == "SLEEP_ROTATIONS":
        return Result(Outcome.SLEEP_ROTATIONS, turns=signed_byte(a[0]))
    elif name == "SIZEOF":
        _push(frame, (_pop(frame) & 0xFF).bit_count(), target)
    elif name == "NEGATE":
        value = -_pop(frame)
        _push(frame, value if target.quirks.negate_wraps else saturated(value), target)
    elif name == "ACTIVATE_DEBUG":
        frame.debug = True
    elif name == "APPLY":
        f = _pop(frame)
        arg = _pop(frame)
        frame.at = at
        if f == 64 and target.quirks.apply_64_broadcasts:
            m.send_command(ANY_ROLE, arg & 0xFF, 0)  # the firmware's broadcast: command a, every role
        else:
            m.eval_command(f & 0xFF, arg)
        _push(frame, 0, target)
    elif name == "PUSH_ARGUMENT":
        _push(frame, frame.arg, target)
    elif name == "PUSHC":
        _push(frame, signed_byte(a[0]), target)
    elif name == "SET_LED":
        m.set_led(signed_byte(a[0]))
    elif name == "SEND_COMMAND_STACK_ARG":
        frame.at = at
        m.send_command(a[0], a[1], _pop(frame))
    elif name == "EVAL_COMMAND_STACK_ARG":
        frame.at = at
        m.eval_command(a[0], _pop(frame))
    elif name == "LOAD_STATE":
        _push(frame, m.load_state(_state(a[0])), target)
    elif name == "STORE_STATE":
        value = _pop(frame)
        frame.at = at
        m.store_state(_state(a[0]), value)
    elif name == "NBR_AGG":
        _push(frame, m.neighbour_values(a[0], a[1]), target)
    elif name == "DATA":
        raise VMError("DATA is the value the program carries, not an instruction to run")
    elif name == "LOAD_DATA":
        _push(frame, m.load_data(), target)
    elif name == "STORE_DATA":
        m.store_data(_pop(frame))
    elif name == "SET_LED_STACK":
        m.set_led(_pop(frame))
    elif name == "RUN_LOCAL":
        frame.at = at
        m.run_local(_embedded(frame, a[0], a[1]))
    elif name == "TABLE":  # a step's action code by the progress (rdcd_core/sequences/lower.py)
        data = _embedded(frame, a[0], a[1])
        i = _pop(frame)
        _push(frame, data[i] - PUSH_SMALL_BASE if 0 <= i < len(data) else 0, target)
    elif name == "CONTINUE_COMMAND":  # a fragment's code that did not fit goes on elsewhere
        code = m.command_code(a[0])
        if code is None:
            raise VMError(f"CONTINUE_COMMAND: no code for command {a[0]} here")
        frame.code, frame.pc = code, 0
    elif name == "ACT":  # a compact sequence step's action by its code (vm.isa.opcodes.step_action)
        action = step_action(_pop(frame))
        if action is None:
            _push(frame, 0, target)
        else:
            frame.at = at
            m.start_action(action[0], action[1], frame.code, at)
            return Result(Outcome.ACTION)
    elif name in ACTIONS:
        # the world answers later: the runtime resumes the frame and pushes 1 or 0 (the result
        # counts in the verifier's stack depth like any push)
        frame.at = at
        m.start_action(ACTIONS[name], _pop(frame), frame.code, at)
        return Result(Outcome.ACTION)
    elif name == "IS_CONNECTED":
        _push(frame, int(m.is_connected(_pop(frame))), target)
    elif name == "IS_ALIGNED":
        _push(frame, int(m.is_aligned(_pop(frame))), target)
    # NOP: nothing
    return None
