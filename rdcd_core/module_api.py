"""The Module API of docs/language.md: the one table that the checker, the compiler, hover,
completion, signature help and the editor grammar read (docs/architecture.md rule 1)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from rdcd_core.types import Type
from vm.isa.opcodes import ANGLE_STEP, ANGLES_BY, ANGLES_TO, SPEEDS, TABLE_VALUES, TURNS


class CallForm(StrEnum):
    SELF = "self"  # self.name(...)
    FUNCTION = "function"  # name(...)


@dataclass(frozen=True, slots=True)
class Param:
    name: str
    type: Type


@dataclass(frozen=True, slots=True)
class Primitive:
    name: str
    form: CallForm
    params: tuple[Param, ...]
    result: Type
    doc: str
    aggregate: bool = False  # also takes one argument: the neighbours' values of a state
    # The values the (first) argument may take, (low, high, step): the checker refuses a constant
    # outside them (E210, E211) and the VM's stack instruction a value known only at run time.
    values: tuple[int, int, int] | None = None
    runtime_op: str | None = None  # the instruction that takes a value known only at run time
    variadic: bool = False  # the last parameter repeats (at least once): table(i, v0, v1, ...)
    # The argument is an angle in degrees that the compiler turns into tens (the operand of a
    # joint command): written as a number, it may be any angle of ``values`` (turnTowards(150),
    # turnDegrees(-180)), beyond the -128..127 of a value.
    degrees: bool = False

    @property
    def is_query(self) -> bool:
        """A zero-argument primitive with a value: may be written without parentheses."""
        return self.form is CallForm.SELF and not self.params and self.result is not Type.VOID

    @property
    def block_param(self) -> int | None:
        for index, param in enumerate(self.params):
            if param.type is Type.BLOCK:
                return index
        return None

    @property
    def signature(self) -> str:
        params = ", ".join(f"{p.name}: {p.type.value}" for p in self.params)
        params += ", ..." if self.variadic else ""
        prefix = "self." if self.form is CallForm.SELF else ""
        return f"{prefix}{self.name}({params}) -> {self.result.value}"


def _p(name: str, type_: Type) -> Param:
    return Param(name, type_)


_S, _F = CallForm.SELF, CallForm.FUNCTION
_EVENT = (_p("e", Type.EVENT),)

PRIMITIVES: tuple[Primitive, ...] = (
    Primitive("center_position", _S, (), Type.AXIS,
              "The axis of the module's own rotation joint, in the structure's compass frame."),
    Primitive("total_connected", _S, (), Type.CONNSET,
              "The connectors that have a neighbour attached."),
    Primitive("connected", _S, (_p("d", Type.DIR),), Type.CONNSET,
              "The attached connectors that face direction d."),
    Primitive("x", _S, (), Type.INT,
              "Lattice x coordinate (east) relative to the module where the program entered."),
    Primitive("y", _S, (), Type.INT,
              "Lattice y coordinate (north) relative to the module where the program entered."),
    Primitive("z", _S, (), Type.INT,
              "Lattice z coordinate (up) relative to the module where the program entered."),
    Primitive("sizeof", _F, (_p("s", Type.CONNSET),), Type.INT,
              "The number of connectors in s."),
    Primitive("connected_role", _F, (_p("d", Type.DIR), _p("R", Type.ROLE)), Type.CONNSET,
              "Connectors facing d whose neighbour plays R, a sub-role of R, or R as a mixin."),
    Primitive("turnContinuously", _S, (_p("v", Type.INT),), Type.VOID,
              "Rotate continuously: v > 0 clockwise, v < 0 counter-clockwise, speed abs(v); v in -127..127.",
              values=(*SPEEDS, 1), runtime_op="TURN_STACK"),
    Primitive("turnTowards", _S, (_p("deg", Type.INT),), Type.VOID,
              "Rotate to the absolute joint angle deg: a multiple of 10 in -180..170 when written as "
              "a number; a computed angle is a value, so -120..120.",
              values=(*ANGLES_TO, ANGLE_STEP), runtime_op="TURN_TO_STACK", degrees=True),
    Primitive("turnDegrees", _S, (_p("deg", Type.INT),), Type.VOID,
              "Rotate by deg degrees relative to the current angle: a multiple of 10, in -1280..1270 "
              "when written as a number; a computed angle is a value, so -120..120.",
              values=(*ANGLES_BY, ANGLE_STEP), runtime_op="TURN_BY_STACK", degrees=True),
    Primitive("stopTurning", _S, (), Type.VOID, "Stop the joint."),
    Primitive("sleepWhileTurning", _S, (_p("n", Type.INT),), Type.VOID,
              "Wait until the joint has made n full turns: n in 0..127.",
              values=(*TURNS, 1), runtime_op="SLEEP_ROTATIONS_STACK"),
    Primitive("sleep", _S, (), Type.VOID, "Wait one second."),
    Primitive("handleEvent", _S, (_p("e", Type.EVENT), _p("b", Type.BLOCK)), Type.VOID,
              "Install block b as the handler of event e."),
    Primitive("disableEvent", _S, _EVENT, Type.VOID, "Disable the handler of event e."),
    Primitive("enableEvent", _S, _EVENT, Type.VOID, "Re-enable the handler of event e."),
    Primitive("clearEvent", _S, _EVENT, Type.VOID, "Remove the handler of event e."),
    Primitive("assumeRole", _S, (_p("M", Type.ROLE), _p("b", Type.BLOCK)), Type.VOID,
              "Play mixin M while b runs, then return to the previous role; "
              "neighbours are notified both times."),
    Primitive("setLed", _S, (_p("v", Type.INT),), Type.VOID,
              "Show v on the module's LEDs (debugging).", runtime_op="SET_LED_STACK"),
    Primitive("connect", _S, (_p("c", Type.INT),), Type.BOOL,
              "Latch male connector c (an even physical connector number, 0..7) onto the female "
              "connector of the module on the adjacent cell that faces it; the behaviour waits until "
              "the latch has closed or failed. True if latched. A statement, the condition of an if, "
              "or the value of a state assignment."),
    Primitive("disconnect", _S, (_p("c", Type.INT),), Type.BOOL,
              "Open the latch of male connector c (even, 0..7); waits until done. True if opened; "
              "false if c was not latched. May split the robot in parts that go on running."),
    Primitive("isConnected", _S, (_p("c", Type.INT),), Type.BOOL,
              "Whether physical connector c (0..7) is latched to a neighbour."),
    Primitive("isAligned", _S, (_p("c", Type.INT),), Type.BOOL,
              "Whether a connector of a module on the adjacent cell faces physical connector c "
              "(0..7), latched or not: the firmware's isOtherConnectorNearby."),
    Primitive("turnQuarters", _S, (_p("n", Type.INT),), Type.BOOL,
              "Turn the joint n quarter turns (n > 0 clockwise), carrying everything attached to the "
              "turning hemisphere to new cells; waits until the turn has ended. True if it turned; "
              "false if blocked (a loop through the structure, a module in the way, the ground)."),
    Primitive("act", _S, (_p("a", Type.INT),), Type.BOOL,
              "The action of a sequence step from its code a (the compact form of sequences, "
              "docs/reconfiguration.md): 1..4 disconnect(2 * (a - 1)), 5..8 connect(2 * (a - 5)), "
              "9, 10, 12, 13 turnQuarters(a - 11); waits like them and answers the same. Any other a "
              "answers false at once and does nothing. Placed like connect (an extension, ACT)."),
    Primitive("min", _F, (_p("a", Type.INT), _p("b", Type.INT)), Type.INT,
              "The smaller of a and b; min(neighbours.s): the smallest value of module state s that a "
              "neighbour published (127 when none has).", aggregate=True),
    Primitive("max", _F, (_p("a", Type.INT), _p("b", Type.INT)), Type.INT,
              "The larger of a and b; max(neighbours.s): the largest value of module state s that a "
              "neighbour published (-128 when none has).", aggregate=True),
    Primitive("table", _F, (_p("i", Type.INT), _p("v", Type.INT)), Type.INT,
              "The value v_i of the constants v0, v1, ... (each 0..127), 0 when i is outside "
              "0..n-1: table(S - 3, 1, 0, 9). One byte a value (the DCD-VM's TABLE, an extension); "
              "compact sequences read their steps' actions with it (docs/reconfiguration.md).",
              variadic=True, values=TABLE_VALUES),
    Primitive("count", _F, (_p("v", Type.VALUES),), Type.INT,
              "How many neighbours have published a value of the state: count(neighbours.s)."),
    Primitive("sum", _F, (_p("v", Type.VALUES),), Type.INT,
              "The sum of the neighbours' published values of the state, saturated to -128..127: "
              "sum(children.s)."),
)

SELF_PRIMITIVES: dict[str, Primitive] = {p.name: p for p in PRIMITIVES if p.form is CallForm.SELF}
FUNCTIONS: dict[str, Primitive] = {p.name: p for p in PRIMITIVES if p.form is CallForm.FUNCTION}


def lookup_self(name: str) -> Primitive | None:
    return SELF_PRIMITIVES.get(name)


def lookup_function(name: str) -> Primitive | None:
    return FUNCTIONS.get(name)


# The calls that change the structure: they act, so they are never evaluated twice or in role
# discovery (the checker allows them only where they run exactly once, E320).
ACTIONS = frozenset({"connect", "disconnect", "turnQuarters", "act"})
# The calls whose argument is a physical connector number (a constant is checked, E220).
CONNECTOR_CALLS = frozenset({"connect", "disconnect", "isConnected", "isAligned"})
