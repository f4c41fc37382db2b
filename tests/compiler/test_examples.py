"""The example programs: sizes within the targets, verifier, disassembly round trip."""

from __future__ import annotations

import pytest

from vm.isa.assembler import assemble
from vm.isa.disassembler import to_text
from vm.isa.verifier import verify


def test_obstacle_meets_size_targets(obstacle):
    assert obstacle.diagnostics == []
    assert obstacle.total_bytes <= 180  # stretch target; hand-written code: 200
    assert len(obstacle.fragments) <= 7
    assert obstacle.max_fragment_bytes <= 43
    assert obstacle.injection == [f.name for f in obstacle.fragments]


def test_every_fragment_verifies_strictly(example_programs):
    for program in example_programs.values():
        for fragment in program.fragments:
            assert verify(fragment.code, strict=True) == [], fragment.name
            assert fragment.size <= program.program_budget


def test_every_example_compiles_for_the_original_target():
    """Acceptance 1 of issue 11: every example, for the firmware, within its limits; the obstacle
    program still under the hand-written 200 bytes."""
    from tests.compiler.conftest import _compile, firmware_examples
    from vm.isa.targets import ORIGINAL

    for path in firmware_examples():
        program = _compile(path.read_text(encoding="utf-8"), target="original")
        assert not program.has_errors, (path.name, [d.message for d in program.diagnostics])
        assert program.target == "original"
        for fragment in program.fragments:
            assert verify(fragment.code, target=ORIGINAL) == [], (path.name, fragment.name)
            assert fragment.size <= program.program_budget
        if path.name == "obstacle_avoidance.rdcd":
            assert program.diagnostics == [] and program.total_bytes < 200
            assert len(program.fragments) <= 7 and program.max_fragment_bytes <= 43


def test_disassemble_assemble_identity(example_programs):
    for program in example_programs.values():
        for fragment in program.fragments:
            assert assemble(to_text(fragment.code)) == fragment.code, fragment.name


def test_obstacle_role_table(obstacle):
    roles = {r.name: r for r in obstacle.roles}
    assert [r.id for r in obstacle.roles] == list(range(1, len(obstacle.roles) + 1))
    assert set(roles) == {"RightWheel", "LeftWheel", "Axle", "Wheel", "Reverse",
                          "Reverse@RightWheel", "Reverse@LeftWheel"}
    ids = {name: r.id for name, r in roles.items()}
    assert set(roles["Reverse@LeftWheel"].instance_of) == {
        ids["Reverse@LeftWheel"], ids["Reverse"], ids["LeftWheel"], ids["Wheel"]}
    assert set(roles["RightWheel"].instance_of) == {ids["RightWheel"], ids["Wheel"]}


def test_source_lines_point_into_the_program(obstacle, obstacle_text):
    lines = obstacle_text.count("\n") + 1
    for fragment in obstacle.fragments:
        assert 1 <= fragment.source[0] <= fragment.source[1] <= lines
        assert all(1 <= line <= lines for _, line in fragment.source_lines)
        assert [o for o, _ in fragment.source_lines] == sorted(o for o, _ in fragment.source_lines)


@pytest.mark.parametrize("budget", [30, 40, 50, 71])
def test_budget_is_respected_or_reported(obstacle_text, compile_text, budget):
    program = compile_text(obstacle_text, packet_budget=budget)
    over = [f for f in program.fragments if f.size > budget - 7]
    assert bool(over) == any(d.code in ("W601", "E601") for d in program.diagnostics)
    for fragment in program.fragments:
        assert verify(fragment.code) == []
