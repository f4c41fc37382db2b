"""The DCD-VM instruction set (docs/vm.md): the one table that the VM, the assembler, the
disassembler, the verifier and the compiler read (docs/architecture.md rule 1).

Any byte >= 128 that is not consumed as an operand is "push constant (byte - 128)".
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class Operand(StrEnum):
    DIR = "dir"  # direction code 4..9
    ROLE = "role"  # role id
    EVENT = "event"  # event number 0..7
    TARGET = "target"  # jump target: byte offset from the start of the fragment
    START = "start"  # start offset of an embedded code range
    SIZE = "size"  # size of an embedded code range
    COMMAND = "command"  # command number (1..5 or 128+k)
    BYTE = "byte"  # any byte (signed argument)
    ZERO = "zero"  # a padding operand that must be 0
    STATE = "state"  # a byte of the module's state memory, 0..STATE_SLOTS-1
    GATHER = "gather"  # NBR_AGG: aggregate (bits 4-5: min, max, count, sum) and state (bits 0-2)
    WHERE = "where"  # NBR_AGG: which neighbours (0 all, 1 children, 4..9 a direction, 16+k connector k)


@dataclass(frozen=True, slots=True)
class Instruction:
    opcode: int
    name: str
    operands: tuple[Operand, ...]
    pops: int
    pushes: int
    doc: str
    ext: bool = False  # this project's extension, refused under --strict-isa
    no_fallthrough: bool = False  # control never reaches the next instruction

    @property
    def size(self) -> int:
        return 1 + len(self.operands)


_O = Operand


def _i(opcode: int, name: str, operands: tuple[Operand, ...], pops: int, pushes: int, doc: str,
       *, ext: bool = False, no_fallthrough: bool = False) -> Instruction:
    return Instruction(opcode, name, operands, pops, pushes, doc, ext, no_fallthrough)


INSTRUCTIONS: tuple[Instruction, ...] = (
    _i(1, "CENTER_POSITION_EW", (), 0, 1, "push b(axis = EW)"),
    _i(2, "CENTER_POSITION_NS", (), 0, 1, "push b(axis = NS)"),
    _i(3, "CENTER_POSITION_UD", (), 0, 1, "push b(axis = UD)"),
    _i(4, "CONNECTED", (), 0, 1, "push connset of all connected channels"),
    _i(5, "CONNECTED_SIZEOF", (), 0, 1, "push number of connected channels"),
    _i(6, "EQUALS_0", (), 1, 1, "pop a; push b(a = 0)"),
    _i(7, "EQUALS_1", (), 1, 1, "pop a; push b(a = 1)"),
    _i(8, "EQUALS_2", (), 1, 1, "pop a; push b(a = 2)"),
    _i(9, "EQUALS_3", (), 1, 1, "pop a; push b(a = 3)"),
    _i(10, "EQUALS_4", (), 1, 1, "pop a; push b(a = 4)"),
    _i(11, "CONNECTED_DIR", (_O.DIR,), 0, 1, "push connset of connected channels facing d"),
    _i(12, "CONNECTED_DIR_SIZEOF", (_O.DIR,), 0, 1, "push the size of that connset"),
    _i(13, "END_TERMINATE", (), 0, 0, "end the run, free the slot", no_fallthrough=True),
    _i(14, "END_REPEAT", (), 0, 0, "end the run, queue it again", no_fallthrough=True),
    _i(15, "IF_FALSE_GOTO", (_O.TARGET,), 1, 0, "pop a; if a = 0 jump to t"),
    _i(16, "GOTO", (_O.TARGET,), 0, 0, "jump to t", no_fallthrough=True),
    _i(17, "SET_ROLE_NOTIFY", (_O.ROLE,), 0, 0, "set own role; notify every connected neighbour"),
    _i(18, "MIGRATE_CONTINUE", (), 0, 0,
       "send this program to every neighbour but the sender; end the run", no_fallthrough=True),
    _i(19, "COORD_X", (), 0, 1, "push own x"),
    _i(20, "COORD_Y", (), 0, 1, "push own y"),
    _i(21, "COORD_Z", (), 0, 1, "push own z"),
    _i(22, "GREATER", (), 2, 1, "pop b, pop a; push b(a > b)"),
    _i(23, "LESSER", (), 2, 1, "pop b, pop a; push b(a < b)"),
    _i(24, "COORD_X_GREATER", (), 1, 1, "pop a; push b(x > a)"),
    _i(25, "COORD_X_LESSER", (), 1, 1, "pop a; push b(x < a)"),
    _i(26, "COORD_Y_GREATER", (), 1, 1, "pop a; push b(y > a)"),
    _i(27, "COORD_Y_LESSER", (), 1, 1, "pop a; push b(y < a)"),
    _i(28, "COORD_Z_GREATER", (), 1, 1, "pop a; push b(z > a)"),
    _i(29, "COORD_Z_LESSER", (), 1, 1, "pop a; push b(z < a)"),
    _i(30, "HANDLE_EVENT", (_O.EVENT, _O.START, _O.SIZE), 0, 0,
       "store bytes [start, start+size) of this fragment as the handler of event e"),
    _i(31, "SEND_COMMAND", (_O.ROLE, _O.COMMAND, _O.BYTE), 0, 0,
       "send a command packet on all channels; run it here too if own role is an instance of role"),
    _i(32, "CLEAR_EVENT", (_O.EVENT,), 0, 0, "remove the handler of e and free its slot"),
    _i(33, "EVAL_COMMAND", (_O.COMMAND, _O.BYTE), 0, 0, "run command locally"),
    _i(34, "HAS_ROLE", (_O.ROLE,), 0, 1, "push b(own role is an instance of role)"),
    _i(35, "CONNECTED_ROLE", (_O.DIR, _O.ROLE), 0, 1,
       "push connset of channels facing d whose cached neighbour role is an instance of role"),
    _i(36, "CONNECTED_DOWN_ROLE", (_O.ROLE,), 0, 1, "push b(connected_role(DOWN, role) non-empty)"),
    _i(37, "CONNECTED_UP_ROLE", (_O.ROLE,), 0, 1, "push b(connected_role(UP, role) non-empty)"),
    _i(38, "CONNECTED_EAST_ROLE", (_O.ROLE,), 0, 1, "push b(connected_role(EAST, role) non-empty)"),
    _i(39, "CONNECTED_WEST_ROLE", (_O.ROLE,), 0, 1, "push b(connected_role(WEST, role) non-empty)"),
    _i(40, "CONNECTED_NORTH_ROLE", (_O.ROLE,), 0, 1,
       "push b(connected_role(NORTH, role) non-empty)"),
    _i(41, "CONNECTED_SOUTH_ROLE", (_O.ROLE,), 0, 1,
       "push b(connected_role(SOUTH, role) non-empty)"),
    _i(42, "INSTALL_COMMAND", (_O.ROLE, _O.COMMAND, _O.START, _O.SIZE), 0, 0,
       "store bytes [start, start+size) as user command cmd for every role that is an instance of role"),
    _i(43, "SLEEP", (), 0, 0, "wait one second"),
    _i(44, "DISABLE_EVENT", (_O.EVENT,), 0, 0, "disable the handler of e (no-op if none)"),
    _i(45, "ENABLE_EVENT", (_O.EVENT,), 0, 0, "enable the handler of e (no-op if none)"),
    _i(46, "CLEAR_COMMAND_QUEUE", (_O.COMMAND,), 0, 0, "discard queued, not yet run, commands cmd"),
    _i(47, "IF_TRUE_GOTO", (_O.TARGET,), 1, 0, "pop a; if a != 0 jump to t"),
    _i(48, "SLEEP_ROTATIONS", (_O.BYTE,), 0, 0, "wait until the joint has made n full turns"),
    _i(49, "SIZEOF", (), 1, 1, "pop s; push number of bits set in s"),
    _i(50, "NEGATE", (), 1, 1, "pop a; push -a"),
    _i(51, "ACTIVATE_DEBUG", (), 0, 0, "trace the rest of this run"),
    _i(52, "APPLY", (), 2, 1, "pop f, pop a; run command f with argument a; push 0"),
    _i(53, "PUSH_ARGUMENT", (_O.ZERO,), 0, 1, "push the argument the program was started with"),
    _i(54, "PUSHC", (_O.BYTE,), 0, 1, "push byte"),
    _i(55, "SET_LED", (_O.BYTE,), 0, 0, "show v on the LEDs"),
    _i(56, "EQUALS", (), 2, 1, "pop b, pop a; push b(a = b)", ext=True),
    _i(57, "ADD", (), 2, 1, "pop b, pop a; push a + b (saturated to -128..127)", ext=True),
    _i(58, "SUB", (), 2, 1, "pop b, pop a; push a - b (saturated to -128..127)", ext=True),
    _i(59, "SEND_COMMAND_STACK_ARG", (_O.ROLE, _O.COMMAND), 1, 0,
       "like SEND_COMMAND with the argument popped", ext=True),
    _i(60, "EVAL_COMMAND_STACK_ARG", (_O.COMMAND,), 1, 0,
       "like EVAL_COMMAND with the argument popped", ext=True),
    _i(61, "LOAD_STATE", (_O.STATE,), 0, 1, "push state byte s", ext=True),
    _i(62, "STORE_STATE", (_O.STATE,), 1, 0,
       "pop v; state byte s := v; a published state (s < 8) that changed is sent to every neighbour; "
       "any change wakes the programs waiting in END_WAIT", ext=True),
    _i(63, "NBR_AGG", (_O.GATHER, _O.WHERE), 0, 1,
       "push the min (127 if none), max (-128 if none), count or saturated sum of the values of "
       "published state g & 7 that the neighbours chosen by w last sent", ext=True),
    _i(64, "MIN", (), 2, 1, "pop b, pop a; push the smaller", ext=True),
    _i(65, "MAX", (), 2, 1, "pop b, pop a; push the larger", ext=True),
    _i(66, "RUN_LOCAL", (_O.START, _O.SIZE), 0, 0,
       "store bytes [start, start+size) of this fragment as a program of this module and queue it "
       "(nothing if the same code is stored already); it never migrates", ext=True),
    _i(67, "END_WAIT", (), 0, 0,
       "end the run; run this program again when a state or a neighbour's published value of this "
       "module changes, or its connections change", ext=True, no_fallthrough=True),
    _i(68, "SET_LED_STACK", (), 1, 0, "pop v; show v on the LEDs", ext=True),
    _i(69, "DATA", (_O.BYTE,), 0, 0,
       "the value the program carries (only as its last instruction, never run): it travels with the "
       "program, and copies that differ only in it are the same program", ext=True, no_fallthrough=True),
    _i(70, "LOAD_DATA", (), 0, 1, "push the value the running program carries (0 if it carries none)",
       ext=True),
    _i(71, "STORE_DATA", (), 1, 0,
       "pop v; the running program carries v from now on, to the modules it migrates to (no-op if it "
       "carries no value)", ext=True),
    # Values known only at run time reach the joint (issue 25): each pops its argument, in the units
    # the program writes (a speed, degrees, turns), and checks it as the checker checks a constant.
    _i(72, "TURN_STACK", (), 1, 0,
       "pop v; turn continuously: v > 0 clockwise at speed v, v < 0 counter-clockwise at speed -v, "
       "0 stops the joint; v = -128 is a runtime error (speeds are -127..127)", ext=True),
    _i(73, "TURN_TO_STACK", (), 1, 0,
       "pop d; rotate to the absolute joint angle d degrees; a runtime error unless d is a multiple "
       "of 10 (a byte holds -120..120 of the -180..170 a constant may name)", ext=True),
    _i(74, "TURN_BY_STACK", (), 1, 0,
       "pop d; rotate by d degrees from the current angle; a runtime error unless d is a multiple "
       "of 10", ext=True),
    _i(75, "SLEEP_ROTATIONS_STACK", (), 1, 0,
       "pop n; wait until the joint has made n full turns; a runtime error if n < 0", ext=True),
    _i(76, "MUL", (), 2, 1, "pop b, pop a; push a * b (saturated to -128..127)", ext=True),
    _i(77, "DIV", (), 2, 1,
       "pop b, pop a; push a / b rounded toward zero (saturated: -128 / -1 is 127); b = 0 is a "
       "runtime error", ext=True),
    _i(78, "MOD", (), 2, 1,
       "pop b, pop a; push a % b = a - b * (a / b), with the sign of a; b = 0 is a runtime error",
       ext=True),
    # connector and joint actions of structures that change (docs/vm.md "Changing shape"); the
    # connector c is a physical connector number (even: male, odd: female), as on the firmware
    _i(79, "CONTINUE_COMMAND", (_O.COMMAND,), 0, 0,
       "go on in the code of user command cmd (the module's role's) from its start, in the same "
       "run with the same argument; a runtime error if the module has no code for cmd",
       ext=True, no_fallthrough=True),
    # a constant table read by index (issue 24: a sequence's steps, one byte each, instead of a
    # comparison and a branch per step); the bytes sit in the fragment after its last instruction,
    # each >= 128, so that every reader that walks the code sees them as pushes that never run
    _i(80, "TABLE", (_O.START, _O.SIZE), 1, 1,
       "pop i; push byte[start + i] - 128 if 0 <= i < size, else 0: the bytes [start, start + size) "
       "of the fragment are a table of values 0..127 (each byte >= 128), never run", ext=True),
    _i(90, "CONNECT", (), 1, 1,
       "pop c; latch male connector c onto the female connector that faces it; the run waits until "
       "the latch has closed or failed, then pushes 1 (latched) or 0 (failed)", ext=True),
    _i(91, "DISCONNECT", (), 1, 1,
       "pop c; open the latch of male connector c; the run waits, then pushes 1 (opened) or 0 "
       "(failed: c is not latched, or is female with a male partner)", ext=True),
    _i(92, "IS_CONNECTED", (), 1, 1, "pop c; push b(connector c is latched to a neighbour)", ext=True),
    _i(93, "IS_ALIGNED", (), 1, 1,
       "pop c; push b(a connector of a module on the adjacent cell faces connector c)", ext=True),
    _i(94, "TURN_QUARTERS", (), 1, 1,
       "pop n; turn the joint n quarter turns (n > 0 clockwise), carrying everything attached to the "
       "turning hemisphere; the run waits until the turn has ended, then pushes 1 (turned) or 0 "
       "(blocked: a loop, a collision, the ground)", ext=True),
    # the action of a compact sequence step from its one-byte code (issue 24: one behaviour for
    # the three kinds of action instead of one each, so that the step's role keeps command numbers
    # for other code); the codes are STEP_ACTION_CODES below
    _i(95, "ACT", (), 1, 1,
       "pop a; the action of step code a: 1..4 DISCONNECT 2(a - 1), 5..8 CONNECT 2(a - 5), 9, 10, 12, "
       "13 TURN_QUARTERS a - 11, and the run waits for its answer like theirs (1 or 0); any other a "
       "pushes 0 at once, with no action", ext=True),
    _i(127, "NOP", (), 0, 0, "nothing"),
)

BY_OPCODE: dict[int, Instruction] = {ins.opcode: ins for ins in INSTRUCTIONS}
BY_NAME: dict[str, Instruction] = {ins.name: ins for ins in INSTRUCTIONS}

PUSH_SMALL_BASE = 128  # byte 128 + v pushes v for 0 <= v <= 127
DATA_OPCODE = BY_NAME["DATA"].opcode


def carried_data_offset(code: bytes) -> int | None:
    """Offset of the value a program carries: the operand of a DATA instruction that ends it."""
    if len(code) < 2 or code[-2] != DATA_OPCODE:
        return None
    offset = 0
    while offset < len(code) - 2:  # the DATA must start on an instruction boundary
        op = code[offset]
        info = BY_OPCODE.get(op) if op < PUSH_SMALL_BASE else None
        offset += info.size if info is not None else 1
    return len(code) - 1 if offset == len(code) - 2 else None


def saturated(value: int) -> int:
    """``value`` clamped to -128..127: RDCD's arithmetic saturates (a count stays at 127)."""
    return -128 if value < -128 else 127 if value > 127 else value


def divided(a: int, b: int) -> int:
    """DIV: ``a / b`` rounded toward zero, as C does, saturated (-128 / -1 is 127). ``b`` != 0."""
    quotient = abs(a) // abs(b)
    return saturated(quotient if (a < 0) == (b < 0) else -quotient)


def remainder(a: int, b: int) -> int:
    """MOD: ``a - b * (a / b)`` with DIV's rounding toward zero, so the sign is a's (-7 % 2 is -1)."""
    quotient = abs(a) // abs(b)
    return a - b * (quotient if (a < 0) == (b < 0) else -quotient)


def signed_byte(value: int) -> int:
    """``value`` wrapped to the VM's values, signed bytes -128..127 (stack, operands, coordinates)."""
    return ((value + 128) & 0xFF) - 128


MAX_STACK = 16
MAX_STEPS_PER_RUN = 255
SLOT_BYTES = 64  # a program store slot holds at most this many bytes (docs/vm.md)
PROGRAM_SLOTS = 10  # programs a module stores at once
STATE_SLOTS = 32  # bytes of state a module holds (values of the program's states)
PUBLISHED_SLOTS = 8  # states 0..7 are published: neighbours keep the last value each sent
AGGREGATES = ("min", "max", "count", "sum")  # NBR_AGG's aggregate, bits 4-5 of its first operand
WHERE_ALL, WHERE_CHILDREN, WHERE_CONNECTOR = 0, 1, 16  # NBR_AGG's second operand (4..9: a direction)
ROLE_IDS = 14  # a ROLE operand names role 1..ROLE_IDS, 0 (no role) or 255 (any; vm/roles.py)

# The COMMAND operand: the joint's built-in commands, then user command k as USER_COMMAND_BASE + k.
ROTATE_CW, ROTATE_CCW, STOP, ROTATE_DEGREES, ROTATE_TO = 1, 2, 3, 4, 5
BUILTIN_COMMANDS: dict[int, str] = {ROTATE_CW: "ROTATE_CW", ROTATE_CCW: "ROTATE_CCW", STOP: "STOP",
                                    ROTATE_DEGREES: "ROTATE_DEGREES", ROTATE_TO: "ROTATE_TO"}
USER_COMMAND_BASE = 128
USER_COMMANDS = 5  # entries in a role's command table
USER_COMMAND_NUMBERS = range(USER_COMMAND_BASE, USER_COMMAND_BASE + USER_COMMANDS)
COMMANDS = frozenset(BUILTIN_COMMANDS) | frozenset(USER_COMMAND_NUMBERS)

# What the joint accepts, checked by the checker for a constant (E210, E211) and by TURN_STACK,
# TURN_TO_STACK, TURN_BY_STACK and SLEEP_ROTATIONS_STACK for a value known only at run time.
TABLE_VALUES = (0, 127, 1)  # TABLE's entries: one byte each, 128 + v (a push that never runs)
SPEEDS = (-127, 127)  # turnContinuously: -128 has no opposite speed (-(-128) saturates to 127)
ANGLES_TO = (-180, 170)  # turnTowards: a multiple of 10 (ANGLE_STEP)
ANGLES_BY = (-1280, 1270)  # turnDegrees: a multiple of 10, the operand of ROTATE_DEGREES in tens
ANGLE_STEP = 10
TURNS = (0, 127)  # sleepWhileTurning

# the actions whose run waits for the world's answer (vm.interpreter Outcome.ACTION)
ACTIONS = {"CONNECT": "connect", "DISCONNECT": "disconnect", "TURN_QUARTERS": "turn"}


def step_action(code: int) -> tuple[str, int] | None:
    """ACT's code a as (action, argument) in ACTIONS' words: 1..4 disconnect connector 2(a - 1),
    5..8 connect 2(a - 5), 9, 10, 12, 13 turn a - 11 quarters; None for any other value (no action).
    The compact form of sequences writes these codes (rdcd_core/sequences/compact.py)."""
    if 1 <= code <= 4:
        return "disconnect", 2 * (code - 1)
    if 5 <= code <= 8:
        return "connect", 2 * (code - 5)
    if code in (9, 10, 12, 13):
        return "turn", code - 11
    return None
