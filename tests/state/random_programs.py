"""The random programs of the state fuzz tests (test_state_adversarial.py, test_operators_fuzz.py):
three states a, b, c, a role R whose behaviour or startup runs random statements over them, a role
S, and a run of car7 in the lattice world at 10 % packet loss. Each test gives its own atoms,
operators and statements."""

from __future__ import annotations

from collections.abc import Sequence

from hypothesis import strategies as st

from rdcd_core.compiler.program import CompiledProgram
from sim.config import load_config
from sim.run import role_table
from vm.lattice.world import LatticeWorld

NAMES = ("a", "b", "c")


@st.composite
def expressions(draw: st.DrawFn, atoms: Sequence[str], ops: Sequence[str], max_depth: int,
                depth: int = 0) -> str:
    """A parenthesised binary expression over ``atoms``, nested at most ``max_depth + 1`` deep."""
    if depth > max_depth or draw(st.booleans()):
        return draw(st.sampled_from(atoms))
    op = draw(st.sampled_from(ops))
    left = draw(expressions(atoms, ops, max_depth, depth + 1))
    return f"({left} {op} {draw(expressions(atoms, ops, max_depth, depth + 1))})"


@st.composite
def programs(draw: st.DrawFn, statements: st.SearchStrategy[str], max_statements: int,
             invariants: Sequence[str] = ("",)) -> str:
    body = " ".join(draw(st.lists(statements, min_size=1, max_size=max_statements)))
    invariant = draw(st.sampled_from(invariants))
    kind = draw(st.sampled_from(("behavior", "startup")))
    head = f"{invariant} " if invariant else ""
    return (f"state a := {draw(st.integers(-128, 127))};\nstate b := 0;\nstate c := 127;\n"
            f"role R {{ {head}{kind} go() {{ {body} }} }}\nrole S {{ }}\ndeployment {{ R, S }}\n")


def run_car7(program: CompiledProgram, seed: int) -> LatticeWorld:
    """Five seconds of car7 in the lattice world at 10 % packet loss, the program injected."""
    world = LatticeWorld(load_config("car7"), role_table(program), seed=seed, packet_loss=0.1)
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(5.0)
    return world
