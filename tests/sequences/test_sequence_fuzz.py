"""Fuzzed sequences through the parser, the checker (with the lattice run) and the compiler: no
input raises or reports an internal error (E100), and every diagnostic lies in the text."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from tests.syntax.fuzz_inputs import edit, tokens_of

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EIGHT = (EXAMPLES / "eight_to_snake.rdcd").read_text()
HEAD, _, TAIL = EIGHT.partition("sequence eightToSnake(eight7) {")
TAIL = TAIL[TAIL.index("}") + 1:]

ROLES = st.sampled_from(["UpperLeft", "LowerRight", "Hub", "Side", "Nobody", "Module"])
ACTIONS = st.sampled_from(["connect", "disconnect", "turnQuarters", "waitUntil", "rotate"])
ARGS = st.one_of(st.integers(-9, 130).map(str), st.sampled_from(["self.x() > 0", "", "1, 2", "{ }",
                                                                  "self.connect(0)", "EAST"]))
CONDITIONS = st.one_of(st.none(), st.sampled_from([
    "self.x() == 1", "self.y() < 0", "1", "max(neighbours.eightToSnake) > 0", "self.turnQuarters(1)"]))
STEP = st.builds(lambda r, c, a, x: f"{r}{'(' + c + ')' if c else ''}.{a}({x});",
                 ROLES, CONDITIONS, ACTIONS, ARGS)
ITEM = st.one_of(STEP, st.lists(STEP, max_size=3).map(lambda s: "parallel { " + " ".join(s) + " }"))
CONFIGS = st.sampled_from(["(eight7)", "(car7)", "(snake1)", "", "(nosuch)", "(random30-seed4)"])


def check(text: str) -> None:
    result = check_text(text)
    for d in result.diagnostics:
        assert d.code != "E100", d.message
        assert 0 <= d.span.start <= d.span.end <= len(text)
    if not result.has_errors:
        program = compile_model(result.model, text=text)
        assert all(d.code != "E100" for d in program.diagnostics)
        for sequence in result.program.sequences:
            reversed_program = compile_model(result.model, text=text, reverse=sequence.name.text)
            assert all(d.code != "E100" for d in reversed_program.diagnostics)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(CONFIGS, st.lists(ITEM, max_size=8))
def test_generated_sequences(config: str, items: list[str]) -> None:
    check(HEAD + f"sequence s{config} {{\n" + "\n".join(items) + "\n}\n" + TAIL)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.sampled_from(["insert", "delete", "replace"]), st.integers(0, 400),
                          st.sampled_from(["sequence", "parallel", "(", ")", "{", "}", ";", ".",
                                           "UpperLeft", "connect", "0", "-", "eight7"])), max_size=4))
def test_edited_example(edits: list[tuple[str, int, str]]) -> None:
    tokens = tokens_of(EIGHT)
    for operation, index, word in edits:
        edit(tokens, operation, index % max(1, len(tokens)), word)
    check(" ".join(tokens))


def test_a_huge_sequence_is_refused_quickly() -> None:
    steps = "UpperLeft.waitUntil(1 == 1);\n" * 5000
    result = check_text(HEAD + "sequence s(eight7) {\n" + steps + "}\n" + TAIL)
    assert [d.code for d in result.diagnostics] == ["E803"]
