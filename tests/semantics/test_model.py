"""The checked model: copy-down, folded constants, references, per-concrete-role resolution."""

from __future__ import annotations

from rdcd_core.semantics.model import RoleKind, Value
from rdcd_core.types import Type
from tests.conftest import EXAMPLES
from tests.semantics.fixes import apply_fix as _apply


def _obstacle(check):  # type: ignore[no-untyped-def]
    return check((EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8"))


def test_roles_and_kinds(check) -> None:
    model = _obstacle(check).model
    assert model.roles["Wheel"].kind is RoleKind.ABSTRACT
    assert model.roles["RightWheel"].kind is RoleKind.CONCRETE
    assert model.roles["Reverse"].kind is RoleKind.MIXIN
    assert model.roles["Reverse"].modifies == "Wheel"
    assert model.roles["RightWheel"].parent == "Wheel"
    assert model.roles["Axle"].parent == "Module"
    assert model.deployment == ["RightWheel", "LeftWheel", "Axle"]


def test_copy_down_with_folded_values(check) -> None:
    right = _obstacle(check).model.roles["RightWheel"]
    assert right.constants["turn_direction"].value == Value(Type.INT, 1)
    assert right.constants["connected_direction"].value == Value(Type.DIR, 4)
    assert right.constants["event_handler"].value == Value(Type.EVENT, 5)
    assert right.constants["event_handler"].owner == "RightWheel"
    assert set(right.methods) == {"move", "stop"}
    assert right.methods["stop"].owner == "Wheel"
    assert len(right.invariants) == 4
    wheel = _obstacle(check).model.roles["Wheel"]
    assert wheel.constants["turn_direction"].definition is None
    assert wheel.constants["turn_direction"].type is Type.INT  # from its definitions


def test_negative_constant_and_minus_128(check) -> None:
    checked = check("role A { constant k := -128; constant j := -(1 + 2); }\ndeployment { A }")
    assert checked.diagnostics == [], checked.summary()
    constants = checked.model.roles["A"].constants
    assert constants["k"].value == Value(Type.INT, -128)
    assert constants["j"].value == Value(Type.INT, -3)


def test_constants_referring_to_constants_fold_per_role(check) -> None:
    checked = check("abstract role W { abstract constant a; constant b := a + 1;\n"
                    "  startup s() { self.setLed(b); } }\n"
                    "role R extends W { constant a := 2; }\nrole S extends W { constant a := 5; }\n"
                    "deployment { R, S }")
    assert not checked.result.has_errors, checked.summary()
    assert checked.model.roles["R"].constants["b"].value == Value(Type.INT, 3)
    assert checked.model.roles["S"].constants["b"].value == Value(Type.INT, 6)


def test_folded_overflow_is_reported_for_the_role_that_causes_it(check) -> None:
    checked = check("abstract role W { abstract constant a;\n"
                    "  startup s() { self.setLed(a + 100); } }\n"
                    "role R extends W { constant a := 2; }\nrole S extends W { constant a := 50; }\n"
                    "deployment { R, S }")
    [error] = checked.with_code("E204")
    assert checked.line(error) == 2 and "'S'" in error.message and "150" in error.message


def test_references(check) -> None:
    checked = _obstacle(check)
    refs = checked.model.references
    by_kind = {}
    for ref in refs:
        by_kind.setdefault(ref.kind, set()).add(ref.target)
    assert {"Wheel", "RightWheel", "Reverse", "Axle"} <= by_kind["role"]
    assert "Wheel.connected_direction" in by_kind["constant"]
    assert "Wheel.stop" in by_kind["command"]
    assert {"sizeof", "connected_role", "turnContinuously", "assumeRole"} <= by_kind["primitive"]
    assert {"EAST_WEST", "UP", "DOWN", "EAST"} <= by_kind["predefined"]
    definitions = {(r.kind, r.target) for r in refs if r.is_definition}
    assert ("role", "Wheel") in definitions
    assert ("constant", "RightWheel.turn_direction") in definitions
    assert ("command", "Wheel.stop") in definitions
    text = checked.text
    for ref in refs:
        assert text[ref.name.span.start:ref.name.span.end] == ref.name.text
    uses = [r for r in refs if r.target == "Wheel.turn_direction"]
    assert sum(r.is_definition for r in uses) == 1 and len(uses) == 4


def test_abstract_constant_used_in_abstract_role_resolves_per_concrete_role(check) -> None:
    checked = check("abstract role W { abstract constant d;\n  sizeof(self.connected(d)) == 1; }\n"
                    "role R extends W { constant d := 1; }\nrole S extends W { constant d := UP; }\n"
                    "deployment { R, S }")
    codes = checked.codes()
    assert "E303" in codes  # in R, d is an int where a dir is needed
    assert "E207" in codes


def test_missing_members_named_each_with_fixes(check) -> None:
    checked = check("abstract role W { abstract constant a, b; abstract command c(); }\n"
                    "role R extends W { constant a := 1; }\ndeployment { R }")
    [error] = checked.with_code("E110")
    assert "'b'" in error.message and "'c'" in error.message and "'a'" not in error.message
    assert len(error.related) == 2
    titles = [fix.title for fix in error.fixes]
    assert "declare 'R' abstract" in titles
    assert any("add the missing" in t for t in titles)
    abstract_fix = error.fixes[0]
    edited = _apply(checked.text, abstract_fix)
    assert "abstract role R extends W" in edited
    added = _apply(checked.text, error.fixes[1])
    assert check(added).with_code("E110") == []


def test_missing_constant_fix_uses_the_constant_type(check) -> None:
    checked = check("abstract role W { abstract constant d; }\nrole A extends W { constant d := UP; }\n"
                    "role B extends W { }\ndeployment { A, B }")
    [error] = checked.with_code("E110")
    fixed = _apply(checked.text, error.fixes[1])
    assert "constant d := EAST;" in fixed
    assert check(fixed).diagnostics == [] or "E" not in "".join(check(fixed).codes())


def test_did_you_mean_fix_replaces_the_name(check) -> None:
    checked = check("role A { self.center_position == EAST_WST; }\ndeployment { A }")
    [error] = checked.with_code("E201")
    assert "did you mean 'EAST_WEST'" in error.message
    assert check(_apply(checked.text, error.fixes[0])).diagnostics == []
