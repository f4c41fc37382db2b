"""Issue 25: values known only at run time reach every Module API call (TURN_STACK, TURN_TO_STACK,
TURN_BY_STACK, SLEEP_ROTATIONS_STACK, SET_LED_STACK) and the operators * / % (MUL, DIV, MOD). A
value out of range or a zero divisor is a runtime error that names the value; the report adds the
module, the fragment, the pc and the source line; the module goes on."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.report import _errors
from sim.run import role_table
from vm.interpreter import Frame, Outcome, run
from vm.isa.assembler import assemble
from vm.isa.opcodes import BY_NAME, ROTATE_CCW, ROTATE_CW, ROTATE_DEGREES, ROTATE_TO, STOP
from vm.isa.targets import ORIGINAL
from vm.isa.verifier import verify
from vm.lattice.world import LatticeWorld

PROGRAMS = Path(__file__).resolve().parents[1] / "data" / "runtime_values"


class Joint:
    """A module that records the joint commands a program asks for."""

    def __init__(self) -> None:
        self.commands: list[tuple[int, int]] = []

    def eval_command(self, command: int, arg: int) -> None:
        self.commands.append((command, arg))

    def __getattr__(self, name: str):  # noqa: ANN204
        return lambda *args: 0


def execute(value: int, op: str) -> tuple[Joint, object]:
    joint = Joint()
    code = assemble(f"PUSHC {value}\n{op}\nEND_TERMINATE")
    assert verify(code) == []
    return joint, run(Frame(code), joint)


@pytest.mark.parametrize(("value", "expected"), [(5, (ROTATE_CW, 5)), (-3, (ROTATE_CCW, 3)), (0, (STOP, 0)),
                                                 (127, (ROTATE_CW, 127)), (-127, (ROTATE_CCW, 127))])
def test_turn_stack_turns_by_the_sign(value: int, expected: tuple[int, int]) -> None:
    joint, result = execute(value, "TURN_STACK")
    assert result.outcome is Outcome.TERMINATE and joint.commands == [expected]


@pytest.mark.parametrize(("op", "value", "expected"), [
    ("TURN_TO_STACK", 30, (ROTATE_TO, 3)), ("TURN_TO_STACK", -120, (ROTATE_TO, -12)),
    ("TURN_BY_STACK", -90, (ROTATE_DEGREES, -9)), ("TURN_BY_STACK", 0, (ROTATE_DEGREES, 0))])
def test_angles_from_the_stack(op: str, value: int, expected: tuple[int, int]) -> None:
    joint, result = execute(value, op)
    assert result.outcome is Outcome.TERMINATE and joint.commands == [expected]


def test_turns_from_the_stack_suspend_the_run() -> None:
    _, result = execute(3, "SLEEP_ROTATIONS_STACK")
    assert result.outcome is Outcome.SLEEP_ROTATIONS and result.turns == 3


@pytest.mark.parametrize(("op", "value", "words"), [
    ("TURN_STACK", -128, "speed -128 is outside -127..127"),
    ("TURN_TO_STACK", 127, "127 degrees is not a multiple of 10"),
    ("TURN_BY_STACK", -5, "-5 degrees is not a multiple of 10"),
    ("SLEEP_ROTATIONS_STACK", -1, "-1 turns is outside 0..127")])
def test_out_of_range_values_are_runtime_errors_that_name_them(op: str, value: int, words: str) -> None:
    joint, result = execute(value, op)
    assert result.outcome is Outcome.ERROR and words in result.message and result.pc == 2
    assert joint.commands == []


@pytest.mark.parametrize(("a", "b", "quotient", "rest"), [
    (7, 2, 3, 1), (-7, 2, -3, -1), (7, -2, -3, 1), (-7, -2, 3, -1), (-128, -1, 127, 0), (-128, 1, -128, 0),
    (127, 127, 1, 0), (0, -5, 0, 0), (5, 7, 0, 5)])
def test_division_rounds_toward_zero_and_the_remainder_has_the_sign_of_the_dividend(
        a: int, b: int, quotient: int, rest: int) -> None:
    for op, expected in (("DIV", quotient), ("MOD", rest)):
        frame = Frame(assemble(f"PUSHC {a}\nPUSHC {b}\n{op}\nEND_TERMINATE"))
        assert run(frame, Joint()).outcome is Outcome.TERMINATE and frame.stack == [expected], (op, a, b)


@pytest.mark.parametrize("op", ["DIV", "MOD"])
def test_a_zero_divisor_is_a_runtime_error(op: str) -> None:
    result = run(Frame(assemble(f"PUSHC 9\nPUSHC 0\n{op}\nEND_TERMINATE")), Joint())
    assert result.outcome is Outcome.ERROR and "division by zero: 9" in result.message


def test_multiplication_saturates() -> None:
    for a, b, expected in ((20, 10, 127), (-20, 10, -128), (-128, -1, 127), (-16, 8, -128), (11, -11, -121)):
        frame = Frame(assemble(f"PUSHC {a}\nPUSHC {b}\nMUL\nEND_TERMINATE"))
        run(frame, Joint())
        assert frame.stack == [expected]


def test_the_firmware_halts_on_the_new_instructions() -> None:
    for name in ("TURN_STACK", "TURN_TO_STACK", "TURN_BY_STACK", "SLEEP_ROTATIONS_STACK", "MUL", "DIV",
                 "MOD"):
        assert BY_NAME[name].ext and not ORIGINAL.implements(BY_NAME[name].opcode)


# ---- the programs ---------------------------------------------------------------------
def compiled(text: str, target: str = "default"):  # noqa: ANN201
    result = check_text(text, target=target)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    return compile_model(result.model, text=text, target=target)


def test_the_wheel_command_go_fits_in_24_bytes() -> None:
    program = compiled((PROGRAMS / "go.rdcd").read_text(encoding="utf-8"))
    assert not any(d.code == "W601" for d in program.diagnostics)
    commands = [f for f in program.fragments if f.kind == "command"]
    assert commands and all(f.size <= 24 for f in commands), [(f.name, f.size) for f in program.fragments]
    assert all(f.size <= program.program_budget for f in program.fragments)


def test_a_behaviour_turning_at_a_state_is_small() -> None:
    program = compiled("state a := 3;\nrole R { behavior b() { self.turnContinuously(a); } }\n"
                       "deployment { R }")
    assert program.diagnostics == [] and program.total_bytes <= 20, program.total_bytes


def test_the_wheels_turn_at_the_speed_they_are_told() -> None:
    program = compiled((PROGRAMS / "go.rdcd").read_text(encoding="utf-8"))
    shape = load_config("car7")
    world = LatticeWorld(shape, role_table(program), seed=1, packet_loss=0.1)
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(40.0)
    roles = world.roles_by_name()
    turned = {}
    for mid, runtime in world.runtimes.items():
        joint = [d for _, kind, d in runtime.event_log if kind == "command" and d["command"] < 128]
        if roles[mid] in ("LeftWheel", "RightWheel"):
            turned[roles[mid]] = joint[-1]
            told = next(s.index for s in program.states if s.name == "told")
            assert runtime.state[told] >= 1
    assert turned == {"RightWheel": {"command": ROTATE_CW, "arg": 2},
                      "LeftWheel": {"command": ROTATE_CCW, "arg": 2}}, turned


ON = "state c := 0;\nstate d := 0;\n"  # lines 1-2; line 5: a behaviour that goes on, line 7: the error
R = "\nrole R {\n  behavior on() { d := 1; }\n  behavior bad() {\n"


@pytest.mark.parametrize(("source", "words", "line"), [
    (f"state v := 127;{R}    self.turnTowards(v); c := 1; }} }}", "127 degrees", 7),
    (f"state v := -128;{R}    self.turnContinuously(v); c := 1; }} }}", "speed -128", 7),
    (f"state v := 0;{R}    c := 5 / v; }} }}", "division by zero: 5 / 0", 7),
    (f"state v := 0;{R}    c := 5 % v; }} }}", "division by zero: 5 % 0", 7),
])
def test_runtime_errors_name_module_line_and_value_and_the_module_goes_on(source: str, words: str,
                                                                          line: int) -> None:
    program = compiled(f"{ON}{source}\ndeployment {{ R }}")
    world = LatticeWorld(load_config("snake5"), role_table(program))
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(5.0)
    index = {s.name: s.index for s in program.states}
    assert len(world.runtimes) == 5
    for runtime in world.runtimes.values():
        entries = [e for e in _errors(program, runtime) if words in e["message"]]
        assert len(entries) == 1, runtime.errors
        assert entries[0]["line"] == line, (entries, line)
        assert not runtime.halted
        assert runtime.state[index["c"]] == 0  # the run ended at the error
        assert runtime.state[index["d"]] == 1  # the module's other programs go on


def test_a_divisor_that_is_zero_in_some_structure_leaves_the_conflict_analysis_undecided() -> None:
    """The checker's conflict analysis computes invariants in every local state; a divisor of 0 in
    some of them is the VM's runtime error, not a value: no verdict, never an exception."""
    text = ("role A { self.center_position == EAST_WEST;\n"
            "  sizeof(self.total_connected()) / sizeof(self.connected(UP)) > 0; }\n"
            "role B { sizeof(self.total_connected()) % sizeof(self.connected(DOWN)) == 1; }\n"
            "deployment { A, B }\n")
    result = check_text(text)
    assert not result.has_errors, result.diagnostics
    assert not compile_model(result.model, text=text).has_errors


# ---- --target original: a table of the values the program sends ------------------------------
TABLE = ("role R {\n  self.x() > 0;\n"
         "  command go(v) { self.turnTowards(v * 10); self.turnContinuously(-v); }\n"
         "  startup s() { R.go(3); R.go(-2); } }\ndeployment { R }\n")


def _command_body(program) -> bytes:  # noqa: ANN001
    from vm.isa.disassembler import disassemble

    for fragment in program.fragments:
        for d in disassemble(fragment.code):
            if d.name == "INSTALL_COMMAND":
                start, size = d.operands[2], d.operands[3]
                return bytes(fragment.code[start:start + size])
    raise AssertionError("no command body")


def test_the_firmware_gets_a_table_of_the_values_the_program_sends() -> None:
    from vm.isa.disassembler import disassemble

    program = compiled(TABLE, target="original")
    assert not program.has_errors, program.diagnostics
    body = _command_body(program)
    assert all(ORIGINAL.implements(d.opcode) for d in disassemble(body) if d.info is not None)
    for sent, expected in ((3, [(ROTATE_TO, 3), (ROTATE_CCW, 3)]), (-2, [(ROTATE_TO, -2), (ROTATE_CW, 2)])):
        joint = Joint()
        assert run(Frame(body, arg=sent), joint, ORIGINAL).outcome is Outcome.TERMINATE
        assert joint.commands == expected, (sent, joint.commands)
    default = compiled(TABLE)  # the default target computes the value instead: no table
    assert {"TURN_TO_STACK", "TURN_STACK"} <= {d.name for d in disassemble(_command_body(default))}


@pytest.mark.parametrize(("change", "words"), [
    ("R.go(-2); R.go(self.x());", "needs TURN_TO_STACK"),  # a value not known when compiling
    ("R.go(-2); R.go(1); R.go(2); R.go(4); R.go(5);", "needs TURN_TO_STACK"),  # more than 4 values
    ("R.go(-20);", "would get -128"),  # -20 * 10 saturates; out of range, and no check at run time
])
def test_without_a_small_known_set_the_firmware_says_why(change: str, words: str) -> None:
    text = TABLE.replace("R.go(-2);", change)
    result = check_text(text, target="original")
    messages = [d.message for d in result.diagnostics if d.code == "E605"]
    assert any(words in m for m in messages), result.diagnostics
