"""Issue 25 through the adversarial harness of the state tests (random_programs.py): random
programs with * / % and values known only at run time in every Module API call, through the parser,
the checker, the compiler and the VM at 10 % packet loss. Nothing raises; an out-of-range value or
a zero divisor is a runtime error that names it, never an internal error; values stay bytes."""

from __future__ import annotations

import re

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from tests.state.random_programs import NAMES, expressions, programs, run_car7
from vm.lattice.world import LatticeWorld

ATOMS = ("a", "b", "c", "0", "1", "-1", "7", "-128", "127", "self.x()", "self.z()", "min(neighbours.a)",
         "count(children.a)", "max(b, c)")
OPS = ("+", "-", "*", "/", "%")
CALLS = ("self.turnContinuously({})", "self.turnTowards({})", "self.turnDegrees({})",
         "self.sleepWhileTurning({})", "self.setLed({})")
# what a run may end with, besides a full store or queue: the values the instructions refuse
EXPECTED = re.compile(r"division by zero|is outside|is not a multiple of 10|store|queue|slot|"
                      r"instructions in one run|stack overflow")
EXPRESSIONS = expressions(ATOMS, OPS, 2)


@st.composite
def statements(draw: st.DrawFn) -> str:
    kind = draw(st.sampled_from(("assign", "call", "if")))
    if kind == "call":
        return draw(st.sampled_from(CALLS)).format(draw(EXPRESSIONS)) + ";"
    assignment = f"{draw(st.sampled_from(NAMES))} := {draw(EXPRESSIONS)};"
    if kind == "assign":
        return assignment
    return f"if ({draw(EXPRESSIONS)} > {draw(EXPRESSIONS)}) {assignment}"


PROGRAMS = programs(statements(), 3)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(PROGRAMS, st.integers(0, 3))
def test_random_programs_with_the_new_operators_compile_and_run_safely(text: str, seed: int) -> None:
    result = check_text(text)
    if result.has_errors:  # a constant zero divisor (E212), 127 * 7 (E204), a fragment over 64 bytes
        assert all(d.code.startswith(("E2", "E6")) for d in result.diagnostics if d.severity == 1), text
        return
    program = compile_model(result.model, text=text)
    if program.has_errors:
        assert all(d.code.startswith(("E6", "W6")) for d in program.diagnostics), program.diagnostics
        return
    for runtime in run_car7(program, seed).runtimes.values():
        assert not runtime.halted
        for _, message in runtime.errors:
            assert "internal error" not in message and EXPECTED.search(message), message
        assert all(-128 <= v <= 127 for v in runtime.state)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(("a", "*", "/", "%", "//", "/*", "*/", "(", ")", "1", "-", "+", ";", " ")),
                max_size=30))
def test_operator_soup_never_raises(tokens: list[str]) -> None:
    """Any mix of the new characters with comments: diagnostics, never an exception."""
    text = "state a := 1;\nrole R { startup s() { a := " + "".join(tokens) + "; } }\ndeployment { R }\n"
    result = check_text(text)
    if not result.has_errors:
        compile_model(result.model, text=text)


def test_the_checker_and_the_compiler_agree_with_the_vm_on_constants() -> None:
    """A folded constant is what the VM computes at run time from the same operands."""
    for a, op, b in ((7, "/", 2), (-7, "/", 2), (-7, "%", 2), (7, "%", -2), (-128, "/", 1), (12, "*", -10)):
        folded = check_text(f"state s := {a} {op} ({b});\nrole R {{ }}\ndeployment {{ R }}\n")
        assert not folded.has_errors, folded.diagnostics
        runtime = check_text(f"state s := 0;\nstate x := {a};\nstate y := {b};\n"
                             f"role R {{ startup go() {{ s := x {op} y; }} }}\ndeployment {{ R }}\n")
        constant = compile_model(folded.model)
        computed = compile_model(runtime.model)
        world_constant = LatticeWorld(load_config("snake5"), role_table(constant))
        world_computed = LatticeWorld(load_config("snake5"), role_table(computed))
        for world, program in ((world_constant, constant), (world_computed, computed)):
            for name in program.injection:
                world.inject(program.fragment(name).code)
            world.advance(3.0)
        index = {s.name: s.index for s in computed.states}["s"]
        initial = next(s.initial for s in constant.states if s.name == "s")
        assert {r.state[index] for r in world_computed.runtimes.values()} == {initial}, (a, op, b)


FIRMWARE_ATOMS = ("v", "0", "1", "-1", "3", "30", "-128", "127", "sizeof(self.total_connected())")


@st.composite
def stateless_programs(draw: st.DrawFn) -> str:
    """A command whose calls compute from its argument, constants and the module's connections."""
    def expression(depth: int = 0) -> str:
        if depth > 1 or draw(st.booleans()):
            return draw(st.sampled_from(FIRMWARE_ATOMS))
        return f"({expression(depth + 1)} {draw(st.sampled_from(OPS))} {expression(depth + 1)})"
    calls = " ".join(draw(st.sampled_from(CALLS)).format(expression())
                     + ";" for _ in range(draw(st.integers(1, 3))))
    return f"role R {{ command c(v) {{ {calls} }} startup s() {{ R.c(2); }} }}\ndeployment {{ R }}\n"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(PROGRAMS, stateless_programs()))
def test_for_the_firmware_the_new_operators_are_e605_or_code_it_runs(text: str) -> None:
    """--target original gains no instruction: a program either compiles to opcodes the firmware
    executes, or is refused with E605 (never silently different code)."""
    from vm.isa.disassembler import disassemble
    from vm.isa.targets import ORIGINAL

    result = check_text(text, target="original")
    if any(d.code.startswith(("E0", "E1", "E2", "E3", "E4", "E5")) for d in result.diagnostics):
        return
    program = compile_model(result.model, text=text, target="original")
    if program.has_errors:
        assert "E605" in {d.code for d in program.diagnostics}, program.diagnostics
        return
    for fragment in program.fragments:
        missing = {d.name for d in disassemble(fragment.code) if d.info is not None
                   and not ORIGINAL.implements(d.opcode)}
        assert not missing, (fragment.name, missing, text)
