"""The conflict analysis computes as the VM does: saturating 8-bit arithmetic (state, issue 17). Its witness
is checked on the real interpreter, running the compiled discovery code of each role alone."""

from __future__ import annotations

import re

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from rdcd_core.types import PREDEFINED_VALUES
from vm.interpreter import Frame, Outcome, run

NORTH_SOUTH = PREDEFINED_VALUES["NORTH_SOUTH"].code  # where x, y and z are even (docs/vm.md)
B = "role B { self.x() >= 90; self.y() >= 90; }"


class Module:
    """What discovery code asks of a module: its axis, neighbours and coordinates."""

    def __init__(self, coords: tuple[int, int, int]) -> None:
        self._coords, self.role = coords, 0

    def axis_code(self) -> int:
        return NORTH_SOUTH

    def coords(self) -> tuple[int, int, int]:
        return self._coords

    def connected_virtual(self) -> int:
        return 0

    def set_role_notify(self, role: int) -> None:
        self.role = role

    def __getattr__(self, name: str):  # noqa: ANN204 - anything else does nothing
        return lambda *args: 0


def holds_on_the_vm(role: str, coords: tuple[int, int, int]) -> bool:
    """Whether a module at ``coords`` takes ``role`` (deployed alone), running its discovery code."""
    result = check_text(role + f"\ndeployment {{ {role.split()[1]} }}\n")
    assert not result.has_errors, result.diagnostics
    compiled = compile_model(result.model)
    module = Module(coords)
    for fragment in compiled.fragments:
        if fragment.kind == "discovery":
            assert run(Frame(fragment.code), module).outcome is Outcome.MIGRATE
    return module.role != 0


def conflicts(text: str) -> list[str]:
    return [d.message for d in check_text(text).diagnostics if d.code == "W503"]


def witness(message: str) -> tuple[int, int, int]:
    found = dict(re.findall(r"([xyz]) = (-?\d+)", message))
    return int(found.get("x", 0)), int(found.get("y", 0)), int(found.get("z", 0))


def test_a_conflict_where_the_sum_saturates() -> None:
    """x + y for x, y >= 90 is 180..254, which the VM saturates to 127: A holds with B there."""
    a = "role A { self.x() + self.y() > 0; }"
    assert holds_on_the_vm(a, (90, 90, 0))
    (message,) = conflicts(f"{a}\n{B}\ndeployment {{ A, B }}\n")
    coords = witness(message)
    assert holds_on_the_vm(a, coords) and holds_on_the_vm(B, coords), message


def test_no_conflict_that_only_a_wrapping_sum_would_make() -> None:
    """With 8-bit wrapping, x + y < 0 would hold at x = y = 90; saturated, it never does there."""
    a = "role A { self.x() + self.y() < 0; }"
    assert not holds_on_the_vm(a, (90, 90, 0))
    assert conflicts(f"{a}\n{B}\ndeployment {{ A, B }}\n") == []


def test_negation_saturates_like_the_vm() -> None:
    """-(-128) is 127 on this project's VM (NEGATE saturates): A never holds, so no conflict."""
    a = "role A { self.x() <= -128; -self.x() < 0; }"
    assert not holds_on_the_vm(a, (-128, 0, 0))
    assert conflicts(f"{a}\nrole C {{ self.x() < 0; }}\ndeployment {{ A, C }}\n") == []
