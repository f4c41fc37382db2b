"""Property: compiled discovery code takes exactly the first deployed role whose invariants hold
(docs/language.md), in every local state, despite the state-space simplification of its tests and
also where several roles hold (run on the real interpreter, the fragments one after another on one
module as they arrive)."""

from __future__ import annotations

import re

from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.compiler.geometry import LOCAL_STATES
from rdcd_core.frontend import check_text
from rdcd_core.types import PREDEFINED_VALUES
from vm import navigation
from vm.interpreter import Frame, Outcome, run

DIRS = ["EAST", "WEST", "NORTH", "SOUTH", "UP", "DOWN"]
AXES = ["EAST_WEST", "NORTH_SOUTH", "UP_DOWN"]
OPS = ["==", "!=", "<", ">", "<=", ">="]


class FakeModule:
    def __init__(self, axis: int, connected: int) -> None:
        self.axis, self.connected, self.role = axis, connected, 0

    def axis_code(self):
        return self.axis

    def coords(self):
        return (0, 0, 0)

    def connected_virtual(self):
        return self.connected

    def facing(self, direction):
        return navigation.channels_facing(self.axis, direction)

    def set_role_notify(self, role):
        self.role = role

    def has_role(self, role):
        return self.role == role  # the generated roles extend only an abstract role

    def __getattr__(self, name):
        return lambda *args: 0


atom = st.one_of(
    st.builds(lambda a, n: f"self.center_position {'==' if n else '!='} {a}", st.sampled_from(AXES),
              st.booleans()),
    st.builds(lambda op, k: f"sizeof(self.total_connected()) {op} {k}", st.sampled_from(OPS),
              st.integers(0, 4)),
    st.builds(lambda d, op, k: f"sizeof(self.connected({d})) {op} {k}", st.sampled_from(DIRS),
              st.sampled_from(OPS), st.integers(0, 3)),
    st.builds(lambda d: f"self.connected({d}) > 0", st.sampled_from(DIRS)),
)
invariant = st.one_of(atom, st.builds(lambda a, b, op: f"({a}) {op} ({b})", atom, atom,
                                      st.sampled_from(["&&", "||"])),
                      st.builds(lambda a: f"!({a})", atom))


def program(shared: list[str], own: list[list[str]]) -> str:
    parts = ["abstract role P {", *[f"  {inv};" for inv in shared], "}"]
    for index, invariants in enumerate(own):
        parts += [f"role R{index} extends P {{", *[f"  {inv};" for inv in invariants], "}"]
    names = ", ".join(f"R{i}" for i in range(len(own)))
    return "\n".join(parts) + f"\ndeployment {{ {names} }}\n"


def run_discovery(codes: list[bytes], axis: int, connected: int) -> int:
    module = FakeModule(axis, connected)
    for code in codes:
        result = run(Frame(code), module)
        assert result.outcome is Outcome.MIGRATE, result
    return module.role


def as_python(invariant: str) -> str:
    """The generated invariant as a Python expression over ``axis`` and ``c`` (independent of the
    compiler's own evaluator)."""
    text = invariant.replace("&&", " and ").replace("||", " or ").replace("!(", " not (")
    text = text.replace("sizeof(self.total_connected())", "bits(c)")
    text = re.sub(r"sizeof\(self\.connected\((\w+)\)\)", r"bits(c & facing(axis, \1))", text)
    text = re.sub(r"self\.connected\((\w+)\)", r"(c & facing(axis, \1))", text)
    return text.replace("self.center_position", "axis")


def holds(invariants: list[str], axis: int, connected: int) -> bool:
    names = {name: value.code for name, value in PREDEFINED_VALUES.items()}
    scope = {"axis": axis, "c": connected, "bits": lambda v: bin(v).count("1"),
             "facing": navigation.channels_facing, **names}
    return all(eval(as_python(inv), scope) for inv in invariants)  # noqa: S307 - generated text


@settings(max_examples=80)
@given(st.lists(invariant, max_size=3), st.lists(st.lists(invariant, max_size=2), min_size=1, max_size=3))
def test_discovery_matches_the_invariants(shared, own):
    text = program(shared, own)
    result = check_text(text)
    if any(d.severity == 1 for d in result.diagnostics):
        return
    compiled = compile_model(result.model)
    ids = {r.name: r.id for r in compiled.roles}
    for index in range(0, len(LOCAL_STATES), 5):
        axis, connected = LOCAL_STATES[index]
        winners = [f"R{i}" for i, inv in enumerate(own) if holds(shared + inv, axis, connected)]
        codes = [fragment.code for fragment in compiled.fragments if fragment.kind == "discovery"]
        role = run_discovery(codes, axis, connected)
        assert role == (ids[winners[0]] if winners else 0), (text, axis, bin(connected))


def independent_program(roles: list[list[str]]) -> str:
    """Roles with nothing in common: each is discovered by a fragment of its own."""
    parts = []
    for index, invariants in enumerate(roles):
        parts += [f"role R{index} {{", *[f"  {inv};" for inv in invariants], "}"]
    names = ", ".join(f"R{i}" for i in range(len(roles)))
    return "\n".join(parts) + f"\ndeployment {{ {names} }}\n"


@settings(max_examples=80)
@given(st.lists(st.lists(invariant, max_size=2), min_size=2, max_size=4))
def test_the_first_holding_role_wins_across_fragments(roles):
    """Each role its own fragment (or a group): where several hold, the first deployed is taken,
    and a fragment pays for its guard only when an earlier role can hold where its role holds."""
    text = independent_program(roles)
    result = check_text(text)
    if any(d.severity == 1 for d in result.diagnostics):
        return
    compiled = compile_model(result.model)
    ids = {r.name: r.id for r in compiled.roles}
    codes = [fragment.code for fragment in compiled.fragments if fragment.kind == "discovery"]
    for index in range(0, len(LOCAL_STATES), 3):
        axis, connected = LOCAL_STATES[index]
        winners = [f"R{i}" for i, inv in enumerate(roles) if holds(inv, axis, connected)]
        assert run_discovery(codes, axis, connected) == (ids[winners[0]] if winners else 0), \
            (text, axis, bin(connected))


def test_wheel_before_other_takes_the_wheels():
    """The issue's program: Other has no invariant, so it holds everywhere; Wheel comes first."""
    text = ("role Wheel { self.center_position == EAST_WEST; sizeof(self.total_connected()) == 1; }\n"
            "role Other { }\ndeployment { Wheel, Other }\n")
    compiled = compile_model(check_text(text).model)
    ids = {r.name: r.id for r in compiled.roles}
    codes = [fragment.code for fragment in compiled.fragments if fragment.kind == "discovery"]
    ew = PREDEFINED_VALUES["EAST_WEST"].code
    assert run_discovery(codes, ew, 0b1) == ids["Wheel"]
    assert run_discovery(codes, ew, 0b11) == ids["Other"]
    assert len(codes[1]) == 7  # HAS_ROLE 0; IF_FALSE_GOTO; SET_ROLE_NOTIFY; MIGRATE_CONTINUE
