"""The compact form of sequences (rdcd_core/sequences/compact.py) and the language's
``table(i, v0, ...)``: a program that compiles in the ordinary form keeps it; one that does not is
compiled again with tables; bad arguments of ``table`` are diagnostics."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.frontend import check_text
from rdcd_core.sequences.compact import role_table
from rdcd_core.sequences.lower import lower, ordered_steps
from rdcd_core.syntax.parser import parse

ROOT = Path(__file__).resolve().parents[2]
ROLE = "state a := 0;\nrole A { self.center_position == EAST_WEST; behavior b() { a := %s; } }\n" \
       "role B { }\ndeployment { A, B }\n"


@pytest.mark.parametrize("call, code", [
    ("table(a, 1, 200)", "E204"), ("table(a, 1, -1)", "E211"), ("table(a, a)", "E205"),
    ("table(a)", "E302"), ("table()", "E302"), ("table(a, {})", "E304")])
def test_bad_arguments_of_table_are_diagnostics(call: str, code: str) -> None:
    result = check_text(ROLE % call)
    assert code in {d.code for d in result.diagnostics if d.severity.name == "ERROR"}


def test_table_checks_clean_with_constants() -> None:
    result = check_text(ROLE % "table(a - 1, 0, 127, 5)")
    assert [d for d in result.diagnostics if d.severity.name == "ERROR"] == []


@pytest.mark.parametrize("name", ["eight_to_snake.rdcd"])
def test_programs_that_fit_keep_the_ordinary_form(name: str) -> None:
    from rdcd_core.compiler import compile_model

    text = (ROOT / "examples" / name).read_text()
    result = check_text(text)
    program = compile_model(result.model, text=text)
    assert not program.has_errors
    assert not any(f.name.startswith(("eightToCar_t", "carToSnake_t")) for f in program.fragments)
    assert all(s.name[-2:] not in ("_t", "_k") for s in program.states)


def _sequence(steps: str):  # noqa: ANN202 - the parsed program
    text = f"role R {{ self.x() >= 0; }}\nsequence s {{ {steps} }}\ndeployment {{ R }}\n"
    return parse(text).program


@pytest.mark.parametrize("steps", [
    "R(self.x() == 9).connect(0);",  # key over 8
    "R(self.x() > 1).connect(0);",  # not E == key
    "R(self.x() == 1).connect(1);",  # female connector
    "R(self.x() == 1).turnQuarters(3);",  # three quarters
    "R(self.x() == 1).connect(0); R(self.y() == 1).connect(0);",  # two expressions
    "R.waitUntil(1 == 1);",  # nothing to put in a table
])
def test_steps_without_a_compact_code_keep_the_ordinary_form(steps: str) -> None:
    program = _sequence(steps)
    assert role_table("s", ordered_steps(program.sequences[0]), "R", False) is None


@pytest.mark.parametrize("steps, sizes", [
    (27, [9, 18]),
    (28, [9, 19]),  # one entry more than a middle part holds: the last part, a byte to spare, takes it
    (46, [9, 18, 19]),
    (47, [9, 18, 18, 2]),
])
def test_the_relay_reads_the_table_in_parts_that_fit_a_fragment(steps: int, sizes: list[int]) -> None:
    program = _sequence(" ".join(["R(self.x() == 1).connect(0);"] * steps))
    read, _, _ = role_table("s", ordered_steps(program.sequences[0]), "R", False)
    assert [len(part.split(",")) - 1 for part in read.split(";") if part.strip()] == sizes


def test_the_table_backwards_is_the_undo_in_reverse_order() -> None:
    program = _sequence("R(self.x() == 1).disconnect(2); R(self.x() == 2).turnQuarters(1);")
    steps = program.sequences[0]
    read, startup, acts = role_table("s", ordered_steps(steps), "R", False)
    assert "table(s, 16, 40)" in read and startup == "s_k := (self.x()) * 14;"  # 1*14+2, 2*14+12
    read, _, acts = role_table("s", ordered_steps(steps, True), "R", True)
    assert "table(s, 38, 20)" in read  # turn back -1: 2*14+10; connect(2): 1*14+6
    # one behaviour acts on every code (ACT): one command number, where one per kind took three
    assert [a[0] for a in acts] == ["behavior s_t_R() { if (self.act(s_t)) { s := s + 1; s_t := 0; } }"]


def test_compact_lowering_declares_its_states_once() -> None:
    program = _sequence("R(self.x() == 1).disconnect(2);")
    lowered = lower(program, compact=True)
    names = [s.name.text for s in lowered.states]
    assert names.count("s_t") == 1 and names.count("s_k") == 1


def test_a_compact_lowering_without_tables_declares_none_of_their_states() -> None:
    # key 9 has no code in a table: the ordinary form's code, and no s_t, s_k or lane s_a
    program = _sequence("parallel { R(self.x() == 9).disconnect(2); R(self.x() == 2).disconnect(4); }")
    names = [s.name.text for s in lower(program, compact=True).states]
    assert "s" in names and not {"s_t", "s_k", "s_a"} & set(names)


LONG_KEYS = """role Piece {
  self.z() <= 0;
}

sequence carToSnake(car7) {
  Piece(max(self.x() * 3 + self.y() + 4, self.z() * 2 + self.x()) == 5).turnQuarters(1);
  Piece(max(self.x() * 3 + self.y() + 4, self.z() * 2 + self.x()) == 8).connect(6);
  Piece(max(self.x() * 3 + self.y() + 4, self.z() * 2 + self.x()) == 4).disconnect(6);
}

deployment { Piece }
"""


def test_a_program_whose_ordinary_form_the_robot_would_not_receive_takes_the_compact_form(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # the ordinary form compiles without an error, but two step fragments are over the packet
    # budget and cannot be split (W601, a warning): the robot would never receive them, so the
    # compiler tries the tables, which fit
    import rdcd_core.compiler as compiler
    from rdcd_core.compiler import compile_model

    result = check_text(LONG_KEYS)
    with monkeypatch.context() as patched:  # the ordinary form, as a target without ACT gets it
        patched.setattr(compiler, "_compact_runs", lambda target: False)
        ordinary = compile_model(result.model, text=LONG_KEYS)
    assert "W601" in {d.code for d in ordinary.diagnostics} and not ordinary.has_errors
    program = compile_model(result.model, text=LONG_KEYS)
    assert not program.has_errors and "W601" not in {d.code for d in program.diagnostics}
    assert any(s.name == "carToSnake_k" for s in program.states)  # the key, kept once
    assert max(len(f.code) for f in program.fragments) <= 43
