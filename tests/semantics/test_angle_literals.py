"""An angle written as a number is degrees, not a value: turnTowards takes -180..170 and turnDegrees
-1280..1270 (multiples of 10), as the Module API says, though every value is -128..127. The
compiler turns the degrees into the joint command's tens; a computed angle stays a value."""

from __future__ import annotations

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm.isa.disassembler import disassemble
from vm.isa.opcodes import ROTATE_DEGREES, ROTATE_TO
from vm.lattice.world import LatticeWorld


def _program(call: str, target: str = "default") -> str:
    return f"role A {{ self.x() == 0;\n startup s() {{ {call}; }} }}\ndeployment {{ A }}\n"


def _codes(text: str, target: str = "default") -> list[str]:
    return [d.code for d in check_text(text, target=target).diagnostics]


def _commands(text: str, target: str = "default") -> list[tuple[int, int]]:
    result = check_text(text, target=target)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    program = compile_model(result.model, text=text, target=target)
    assert not program.has_errors, [d.message for d in program.diagnostics]
    return [(d.operands[0], d.operands[1] - 256 if d.operands[1] > 127 else d.operands[1])
            for f in program.fragments for d in disassemble(f.code)
            if d.name == "EVAL_COMMAND" and d.operands[0] in (ROTATE_TO, ROTATE_DEGREES)]


@pytest.mark.parametrize(("call", "command"), [
    ("self.turnTowards(150)", (ROTATE_TO, 15)),
    ("self.turnTowards(-180)", (ROTATE_TO, -18)),
    ("self.turnTowards((-150))", (ROTATE_TO, -15)),
    ("self.turnTowards(170)", (ROTATE_TO, 17)),
    ("self.turnTowards(-0)", (ROTATE_TO, 0)),
    ("self.turnDegrees(200)", (ROTATE_DEGREES, 20)),
    ("self.turnDegrees(1270)", (ROTATE_DEGREES, 127)),
    ("self.turnDegrees(-1280)", (ROTATE_DEGREES, -128)),
])
@pytest.mark.parametrize("target", ["default", "original"])
def test_an_angle_written_as_a_number_is_degrees_beyond_a_value(call: str, command: tuple[int, int],
                                                                 target: str) -> None:
    assert _commands(_program(call), target) == [command]


@pytest.mark.parametrize(("call", "code", "words"), [
    ("self.turnTowards(180)", "E210", "-180..170, but this is 180"),
    ("self.turnTowards(-190)", "E210", "-180..170, but this is -190"),
    ("self.turnTowards(155)", "E210", "multiple of 10 degrees in -180..170, but this is 155"),
    ("self.turnDegrees(1280)", "E210", "this is 1280"),
    ("self.turnDegrees(-1290)", "E210", "this is -1290"),
    ("self.turnTowards(" + "9" * 40 + ")", "E204", "integer of 40 digits"),
    # a value is still a value: a constant, an expression, a state, or another call's argument
    ("self.turnTowards(100 + 50)", "E204", "this expression is 150"),
    ("self.turnTowards(-(150))", "E204", "integer 150"),
    ("self.turnContinuously(150)", "E204", "integer 150"),
    ("self.setLed(150)", "E204", "integer 150"),
])
def test_an_angle_out_of_the_joint_range_or_a_value_out_of_a_byte_is_still_an_error(
        call: str, code: str, words: str) -> None:
    diagnostics = check_text(_program(call)).diagnostics
    assert [d.code for d in diagnostics] == [code], [d.message for d in diagnostics]
    assert words in diagnostics[0].message


def test_a_constant_of_150_is_a_value_and_an_error_even_as_an_angle() -> None:
    text = "role A { constant a := 150;\n startup s() { self.turnTowards(a); } }\ndeployment { A }\n"
    assert _codes(text) == ["E204"]


def test_the_joint_turns_to_the_angle_written_in_the_lattice_world() -> None:
    text = _program("self.turnTowards(-150); self.turnDegrees(200)")
    result = check_text(text)
    program = compile_model(result.model, text=text)
    world = LatticeWorld(load_config("snake3"), role_table(program))
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(5.0)
    entry = next(r for r in world.runtimes.values() if r.position == (0, 0, 0))
    joint = [(d["command"], d["arg"]) for _, kind, d in entry.event_log if kind == "command"]
    assert joint == [(ROTATE_TO, -15), (ROTATE_DEGREES, 20)]
