"""Argument counts and types of every call in the Module API table (docs/language.md)."""

from __future__ import annotations

import pytest

from rdcd_core.module_api import ACTIONS, PRIMITIVES, CallForm, Primitive
from rdcd_core.types import Type

GOOD = {Type.INT: "1", Type.DIR: "UP", Type.EVENT: "EVENT_PROXIMITY_2", Type.ROLE: "M",
        Type.BLOCK: "{ self.sleep(); }", Type.CONNSET: "self.total_connected()",
        Type.AXIS: "EAST_WEST", Type.VALUES: "neighbours.s"}
BAD = {Type.INT: "EAST", Type.DIR: "1", Type.EVENT: "UP", Type.ROLE: "3", Type.BLOCK: "1",
       Type.CONNSET: "1", Type.AXIS: "1", Type.VALUES: "1"}


def _good(primitive: Primitive) -> list[str]:
    if primitive.name in ("turnTowards", "turnDegrees"):
        return ["30"]
    if primitive.name in ("connect", "disconnect"):
        return ["2"]  # a male connector (E220)
    return [GOOD[p.type] for p in primitive.params]


def _program(primitive: Primitive, args: list[str]) -> str:
    prefix = "self." if primitive.form is CallForm.SELF else ""
    call = f"{prefix}{primitive.name}({', '.join(args)})"
    if primitive.result is Type.VOID:
        body = f"startup s() {{ {call}; }}"
    elif primitive.name in ACTIONS:  # an action runs once, where it is written (E320)
        body = f"startup s() {{ if ({call}) {{ self.sleep(); }} }}"
    elif primitive.result is Type.BOOL:
        body = f"{call};"
    elif primitive.result is Type.AXIS:
        body = f"{call} == EAST_WEST;"
    else:
        body = f"{call} > 0;"
    return f"state s := 0;\nrole W {{ {body} }}\nrole M modifies W {{ }}\ndeployment {{ W }}"


@pytest.mark.parametrize("primitive", PRIMITIVES, ids=[p.name for p in PRIMITIVES])
def test_correct_call_is_clean(check, primitive: Primitive) -> None:
    checked = check(_program(primitive, _good(primitive)))
    assert not checked.result.has_errors, checked.summary()


@pytest.mark.parametrize("primitive", PRIMITIVES, ids=[p.name for p in PRIMITIVES])
def test_wrong_argument_count(check, primitive: Primitive) -> None:
    args = _good(primitive) + ["1"]
    checked = check(_program(primitive, args))
    if primitive.variadic:  # table(i, v0, v1, ...): one more value is a longer table
        assert "E302" not in checked.codes(), checked.summary()
    else:
        assert "E302" in checked.codes(), checked.summary()
    if primitive.params:
        checked = check(_program(primitive, [GOOD[p.type] for p in primitive.params[:-1]]))
        assert "E302" in checked.codes(), checked.summary()


@pytest.mark.parametrize(("primitive", "index"),
                         [(p, i) for p in PRIMITIVES for i in range(len(p.params))],
                         ids=[f"{p.name}-{i}" for p in PRIMITIVES for i in range(len(p.params))])
def test_wrong_argument_type(check, primitive: Primitive, index: int) -> None:
    args = _good(primitive)
    args[index] = BAD[primitive.params[index].type]
    checked = check(_program(primitive, args))
    expected = "E401" if primitive.name == "assumeRole" and index == 0 else "E303"
    found = checked.with_code(expected)
    assert found and checked.source(found[0]) == args[index], checked.summary()
