"""assumeRole scoping (docs/language.md) and method rules (§5.1)."""

from __future__ import annotations

BASE = """abstract role Wheel {
  abstract constant speed;
  self.center_position == EAST_WEST;
  command stop() {
    self.assumeRole(Reverse, { self.turnContinuously(speed); self.back(); });
  }
}
role Right extends Wheel { constant speed := 1; self.y() > 0; }
role Left extends Wheel { constant speed := 2; self.y() < 0; }
role Reverse modifies Wheel { constant speed := -1; back() { self.sleep(); } }
"""


def test_mixin_members_shadow_inside_the_block(check) -> None:
    checked = check(BASE + "deployment { Right, Left }")
    assert checked.diagnostics == [], checked.summary()
    targets = {r.target for r in checked.model.references if r.name.text in ("speed", "back")
               and not r.is_definition}
    assert targets == {"Reverse.speed", "Reverse.back"}


def test_mixin_members_are_not_visible_outside_the_block(check) -> None:
    checked = check(BASE.replace("self.back(); });", "}); self.back();") + "deployment { Right, Left }")
    [error] = checked.with_code("E301")
    assert "back" in error.message


def test_assume_role_must_apply_to_every_concrete_owner(check) -> None:
    checked = check("abstract role Base { startup s() { self.assumeRole(M, { }); } }\n"
                    "role Wheel extends Base { self.x() == 0; }\nrole Axle extends Base { self.x() == 2; }\n"
                    "role M modifies Wheel { }\ndeployment { Wheel, Axle }")
    [error] = checked.with_code("E402")
    assert "'M'" in error.message and "'Wheel'" in error.message and "'Axle'" in error.message
    assert error.related


def test_assume_role_of_another_mixin_inside_is_allowed(check) -> None:
    checked = check("role W { startup s() { self.assumeRole(M, { self.assumeRole(N, { }); }); } }\n"
                    "role M modifies W { }\nrole N modifies W { }\ndeployment { W }")
    assert checked.diagnostics == [], checked.summary()


def test_handler_block_is_checked_in_the_base_role(check) -> None:
    checked = check("role W { startup s() { self.handleEvent(EVENT_PROXIMITY_1, {\n"
                    "  self.assumeRole(M, { self.sleep(); }); self.setLed(1); }); } }\n"
                    "role M modifies W { }\ndeployment { W }")
    assert checked.diagnostics == [], checked.summary()


def test_method_of_an_abstract_role_checks_each_concrete_sub_role(check) -> None:
    checked = check("abstract role W { abstract constant deg;\n"
                    "  startup s() { self.turnTowards(deg); } }\n"
                    "role A extends W { constant deg := 30; self.x() == 0; }\n"
                    "role B extends W { constant deg := 35; self.x() == 2; }\ndeployment { A, B }")
    [error] = checked.with_code("E210")
    assert "'B'" in error.message and checked.line(error) == 2


def test_overridden_method_is_checked_where_it_is_inherited_only(check) -> None:
    checked = check("abstract role W { abstract constant k;\n  startup s() { self.setLed(k + 100); } }\n"
                    "role A extends W { constant k := 100; startup s() { } self.x() == 0; }\n"
                    "role B extends W { constant k := 1; self.x() == 2; }\ndeployment { A, B }")
    assert checked.diagnostics == [], checked.summary()


def test_global_command_inherited(check) -> None:
    checked = check("abstract role W { command stop() { } }\nrole R extends W { startup s() { R.stop(); } }"
                    "\ndeployment { R }")
    assert checked.diagnostics == [], checked.summary()


def test_mixin_methods_are_checked_applied_to_base_roles(check) -> None:
    checked = check("role W { self.x() == 0; }\nrole M modifies W { command c() { self.nope(); } }\n"
                    "deployment { W }")
    assert checked.codes() == ["E301"]


def test_recursion_through_three_methods_reported_once(check) -> None:
    checked = check("role A { f() { self.g(); } g() { self.h(); } h() { self.f(); }\n"
                    "  startup s() { self.f(); } }\ndeployment { A }")
    [error] = checked.with_code("E305")
    assert "f -> g -> h -> f" in error.message


def test_partial_tree_from_syntax_errors_is_analyzed(check) -> None:
    checked = check("role A { self.y( > 0; startup s() { self.sleeep(); } }\ndeployment { A }")
    codes = checked.codes()
    assert any(code.startswith("E0") for code in codes)


def test_nested_assume_through_an_inlined_plain_method(check) -> None:
    checked = check("role W { helper() { self.assumeRole(M, { }); }\n"
                    "  startup s() { self.assumeRole(M, { self.helper(); }); } }\n"
                    "role M modifies W { }\ndeployment { W }")
    [error] = checked.with_code("E403")
    assert checked.source(error) == "helper" and checked.line(error) == 2


def test_handler_installed_by_an_inlined_plain_method(check) -> None:
    checked = check("role W { arm() { self.handleEvent(EVENT_PROXIMITY_0, { }); }\n"
                    "  startup s() { self.assumeRole(M, { self.arm(); }); self.arm(); } }\n"
                    "role M modifies W { }\ndeployment { W }")
    [warning] = checked.with_code("W401")
    assert checked.source(warning) == "arm" and checked.line(warning) == 2
