"""State in the compiler (issue 17): it costs only where it is used, and each form compiles to
what the VM runs."""

from __future__ import annotations

import hashlib
from pathlib import Path

from rdcd_core.compiler import compile_model
from rdcd_core.compiler.render import to_json
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm.isa.disassembler import disassemble
from vm.lattice.world import LatticeWorld

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
# sha256 of every fragment (length byte + bytes) before state existed (commit 10d5004)
BEFORE = {
    "obstacle_avoidance.rdcd": "aaaead672b937b8023aa996624e4bf4fd45f335c059b7970b32df40d8085dc0f",
    "snake_wave.rdcd": "4797612bbb63f19ae5120a570dc4e27444e9d7323593d18a2d9533e43ff8de42",
}


def compiled(text: str):  # noqa: ANN201
    result = check_text(text)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    program = compile_model(result.model, text=text)
    assert not program.has_errors, [d.message for d in program.diagnostics]
    return program


def opcodes(program) -> list[str]:  # noqa: ANN001
    return [d.name for f in program.fragments for d in disassemble(f.code)]


def test_programs_without_state_keep_their_bytes() -> None:
    for name, digest in BEFORE.items():
        program = compiled((EXAMPLES / name).read_text(encoding="utf-8"))
        blob = b"".join(bytes([len(f.code)]) + f.code for f in program.fragments)
        assert hashlib.sha256(blob).hexdigest() == digest, name
        assert "states" not in to_json(program)


def test_the_examples_fit_one_fragment_each() -> None:
    sizes = {}
    for name in ("gradient.rdcd", "count.rdcd", "lowest.rdcd"):
        program = compiled((EXAMPLES / name).read_text(encoding="utf-8"))
        assert len(program.fragments) == 1, name
        sizes[name] = program.total_bytes
    assert sizes["gradient.rdcd"] <= 40  # the stretch goal
    assert max(sizes.values()) <= 43


def test_a_value_only_behaviour_waits_and_an_acting_one_repeats() -> None:
    waits = compiled("state s := 0;\nrole R { behavior b() { s := min(neighbours.s) + 1; } }\n"
                     "deployment { R }")
    assert "END_WAIT" in opcodes(waits) and "END_REPEAT" not in opcodes(waits)
    acts = compiled("state s := 0;\nrole R { behavior b() { s := s + 1; self.sleep(); } }\ndeployment { R }")
    assert "END_REPEAT" in opcodes(acts) and "END_WAIT" not in opcodes(acts)


def test_arguments_of_commands_and_plain_methods() -> None:
    text = """state level := 0;
state got := 0;
state twice := 0;
role Node {
  command take(v) { got := v; }
  double(a, b) { twice := a + b + a; }
  startup go() {
    if (self.x() == 0 && self.y() == 0 && self.z() == 0) {
      level := 5;
      Node.take(level + 2);
    }
    self.double(level, 1);
  }
  behavior show() { self.setLed(1); }
}
deployment { Node }
"""
    program = compiled(text)
    names = opcodes(program)
    assert "SEND_COMMAND_STACK_ARG" in names and "PUSH_ARGUMENT" in names
    world = LatticeWorld(load_config("car7"), role_table(program))
    for fragment in program.injection:
        world.inject(program.fragment(fragment).code)
    world.advance(5.0)
    entry = world.runtimes[0]
    assert entry.state[8:11] == [5, 7, 11]  # level; the command's argument; level + 1 + level
    assert all(r.state[10] == 1 for m, r in world.runtimes.items() if m != 0)  # 0 + 1 + 0


def test_a_constant_argument_is_an_operand() -> None:
    program = compiled("state got := 0;\nrole R { command take(v) { got := v; } "
                       "startup s() { R.take(9); } behavior b() { self.setLed(got); } }\ndeployment { R }")
    sends = [d for f in program.fragments for d in disassemble(f.code) if d.name == "SEND_COMMAND"]
    assert sends and sends[0].operands[2] == 9


def test_the_layout_is_in_the_json_output() -> None:
    program = compiled((EXAMPLES / "count.rdcd").read_text(encoding="utf-8"))
    assert to_json(program)["states"] == [
        {"name": "size", "index": 0, "initial": 1, "role": None, "published": True}]


def test_only_states_the_neighbours_read_are_sent() -> None:
    program = compiled("state ticks := 0;\nstate hops := 0;\n"
                       "role R { behavior b() { ticks := ticks + 1; hops := min(neighbours.hops) + 1; "
                       "self.sleep(); } }\ndeployment { R }")
    layout = {s.name: (s.index, s.published) for s in program.states}
    assert layout == {"hops": (0, True), "ticks": (8, False)}
