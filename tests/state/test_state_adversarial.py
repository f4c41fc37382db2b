"""State through the same adversarial tests as the rest of the language (issue 17): random
programs with state through the front end, the compiler and the VM; values at -128 and 127; deep
expressions; 1,000 state declarations; bad input through the real CLI."""

from __future__ import annotations

import subprocess
import sys

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from tests.state.random_programs import NAMES, expressions, programs, run_car7
from vm.lattice.world import LatticeWorld

ATOMS = ("a", "b", "c", "1", "-128", "127", "0", "self.x()", "self.z()", "min(neighbours.a)",
         "max(neighbours(UP).b)", "count(children.a)", "sum(neighbours(3).c)", "min(a, 5)", "max(b, c)")
EXPRESSIONS = expressions(ATOMS, ("+", "-"), 3)


@st.composite
def statements(draw: st.DrawFn) -> str:
    target = draw(st.sampled_from(NAMES))
    value = draw(EXPRESSIONS)
    if draw(st.booleans()):
        return f"{target} := {value};"
    cmp = draw(st.sampled_from(("<", ">", "==", "!=")))
    return f"if ({draw(EXPRESSIONS)} {cmp} {draw(EXPRESSIONS)}) {target} := {value};"


PROGRAMS = programs(statements(), 4, ("", "a > 0;", "self.z() == b;", "count(neighbours.c) >= 0;"))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(PROGRAMS, st.integers(0, 3))
def test_random_state_programs_compile_and_run_safely(text: str, seed: int) -> None:
    result = check_text(text)
    if result.has_errors:
        return
    program = compile_model(result.model, text=text)
    if program.has_errors:  # e.g. a fragment over 64 bytes: reported, never raised
        assert all(d.code.startswith(("E6", "W6")) for d in program.diagnostics), program.diagnostics
        return
    for runtime in run_car7(program, seed).runtimes.values():
        assert not any("internal error" in message for _, message in runtime.errors), runtime.errors
        assert all(-128 <= v <= 127 for v in runtime.state)


def _run(text: str, seconds: float = 3.0) -> LatticeWorld:
    result = check_text(text)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    program = compile_model(result.model, text=text)
    assert not program.has_errors, [d.message for d in program.diagnostics]
    world = LatticeWorld(load_config("snake5"), role_table(program))
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(seconds)
    return world


def test_values_saturate_at_both_ends() -> None:
    world = _run("state hi := 127;\nstate lo := -128;\n"
                 "role R { startup s() { hi := hi + 1; lo := lo - 1; hi := hi + 100; lo := lo - 100; } }\n"
                 "deployment { R }\n")
    for runtime in world.runtimes.values():
        assert runtime.state[8:10] == [127, -128]  # bytes 8.. hold the states no neighbour reads


def test_a_constant_expression_that_overflows_is_an_error() -> None:
    result = check_text("state s := 100 + 100;\nrole R { }\ndeployment { R }\n")
    assert "E204" in {d.code for d in result.diagnostics}


def test_deep_expressions_over_state_are_reported_not_raised() -> None:
    deep = "(" * 150 + "a" + " + 1)" * 150
    text = f"state a := 0;\nrole R {{ startup s() {{ a := {deep}; }} }}\ndeployment {{ R }}\n"
    result = check_text(text)
    assert {"E015"} & {d.code for d in result.diagnostics}
    long_sum = " + ".join(["a"] * 400)
    text = f"state a := 0;\nrole R {{ startup s() {{ a := {long_sum}; }} }}\ndeployment {{ R }}\n"
    result = check_text(text)
    assert result.has_errors  # too long a chain (E016) or too large a fragment: never an exception
    compile_model(result.model)


def test_a_thousand_state_declarations() -> None:
    text = "".join(f"state s{k} := {k % 100};\n" for k in range(1000))
    text += "role R { startup go() { " + " ".join(f"s{k} := s{k} + 1;" for k in range(0, 1000, 50)) + " } }\n"
    text += "deployment { R }\n"
    result = check_text(text)
    codes = [d.code for d in result.diagnostics]
    assert codes.count("E720") == 1
    assert compile_model(result.model).fragments == []  # errors: nothing compiled, nothing raised


def test_rdcd_check_on_broken_state_programs(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "broken.rdcd"
    path.write_text("state := 3;\nstate s := ;\nrole R { startup go() { s := neighbours.s; x := 1; } }\n"
                    "deployment { R }\n", encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", str(path)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stdout + done.stderr
    assert "error[" in done.stdout
