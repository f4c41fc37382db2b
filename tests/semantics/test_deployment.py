"""Deployment, discovery order, role conflicts, dead roles, target limits (docs/language.md)."""

from __future__ import annotations

from tests.semantics.fixes import apply_fix as _apply

ORDER = """role Axle { sizeof(connected_role(DOWN, Wheel)) > 0; self.center_position == UP_DOWN; }
abstract role Wheel { self.center_position == EAST_WEST; }
role Right extends Wheel { sizeof(self.connected(EAST)) > 0; sizeof(self.connected(WEST)) == 0; }
role Left extends Wheel { sizeof(self.connected(WEST)) > 0; sizeof(self.connected(EAST)) == 0; }
deployment { Right, Axle, Left }"""


def test_discovery_order_names_both_roles_and_fix_reorders(check) -> None:
    checked = check(ORDER)
    [warning] = checked.with_code("W501")
    assert "'Axle'" in warning.message and "'Left'" in warning.message
    assert "'Wheel'" in warning.message
    assert checked.source(warning) == "Axle"
    fixed = _apply(checked.text, warning.fixes[0])
    assert "deployment { Right, Left, Axle }" in fixed
    assert check(fixed).diagnostics == []


def test_discovery_cycle_is_a_warning(check) -> None:
    checked = check("role A { sizeof(connected_role(UP, B)) > 0; self.x() == 0; }\n"
                    "role B { sizeof(connected_role(DOWN, A)) > 0; self.x() == 2; }\n"
                    "deployment { A, B }")
    assert checked.codes() == ["W502"]


def test_observing_a_mixin_needs_no_order(check) -> None:
    checked = check("role W { self.center_position == EAST_WEST; }\nrole M modifies W { }\n"
                    "role A { sizeof(connected_role(DOWN, M)) > 0; self.center_position == UP_DOWN; }\n"
                    "deployment { A, W }")
    assert checked.diagnostics == [], checked.summary()


def test_conflict_witness(check) -> None:
    checked = check("role A { self.y() > 0; }\nrole B { self.center_position == EAST_WEST;\n"
                    "  sizeof(self.connected(UP)) == 1; }\ndeployment { A, B }")
    [warning] = checked.with_code("W503")
    assert "'A'" in warning.message and "'B'" in warning.message
    assert "axis EAST_WEST" in warning.message and "y = 1" in warning.message
    assert "connectors {" in warning.message
    assert "such a module takes 'A', the first of the two in the deployment, never 'B'" in warning.message


def test_disjoint_invariants_do_not_conflict(check) -> None:
    for pair in (("self.y() > 0", "self.y() <= 0"),
                 ("self.center_position == EAST_WEST", "self.center_position == UP_DOWN"),
                 ("sizeof(self.total_connected()) == 1", "sizeof(self.total_connected()) == 2"),
                 ("sizeof(self.connected(UP)) == 1 && sizeof(self.total_connected()) == 1",
                  "sizeof(self.connected(DOWN)) > 0 && sizeof(self.total_connected()) == 1")):
        checked = check(f"role A {{ {pair[0]}; }}\nrole B {{ {pair[1]}; }}\ndeployment {{ A, B }}")
        assert checked.diagnostics == [], checked.summary()


def test_conflict_through_neighbour_roles(check) -> None:
    checked = check("role W { self.center_position == EAST_WEST; self.y() > 0; }\n"
                    "role A { sizeof(connected_role(DOWN, W)) > 0; self.center_position == UP_DOWN; }\n"
                    "role B { sizeof(self.connected(DOWN)) > 0; self.center_position == UP_DOWN; }\n"
                    "deployment { W, A, B }")
    [warning] = checked.with_code("W503")
    assert "neighbours playing 'W'" in warning.message


def test_undecidable_invariants_are_skipped(check) -> None:
    checked = check("role A { self.y() > 0; startup s() { } }\n"
                    "role B { self.y() + self.x() > 0; self.y() < 0; }\ndeployment { A, B }")
    assert checked.codes() == []


def test_dead_role_fix_deploys_it(check) -> None:
    checked = check("role A { self.x() == 0; }\nrole Unused { self.x() == 2; }\ndeployment { A }")
    [warning] = checked.with_code("W504")
    assert check(_apply(checked.text, warning.fixes[0])).diagnostics == []


def test_referenced_or_extended_roles_are_not_dead(check) -> None:
    checked = check("role A { self.x() == 0; }\nrole B extends A { self.y() == 0; }\n"
                    "role C { self.x() == 2; startup s() { A.c(); } }\n"
                    "role D { sizeof(connected_role(UP, C)) > 0; self.x() == 4; }\n"
                    "deployment { B, D }")
    assert "W504" not in checked.codes(), checked.summary()


def test_repeated_deployment_fix_removes_it(check) -> None:
    checked = check("role A { }\ndeployment { A, A }")
    [error] = checked.with_code("E504")
    assert check(_apply(checked.text, error.fixes[0])).diagnostics == []


def test_role_id_limit_counts_mixin_applications(check) -> None:
    roles = "".join(f"role R{k} extends B {{ self.x() == {2 * k}; }}\n" for k in range(7))
    text = ("abstract role B { startup s() { self.assumeRole(M, { }); } }\n" + roles
            + "role M modifies B { }\nrole N modifies R0 {}\n"
            + "role O { self.x() == 100; startup s() { self.assumeRole(N, { }); } }\n"
            + "deployment { " + ", ".join(f"R{k}" for k in range(7)) + " }")
    checked = check(text)
    [error] = checked.with_code("E120")  # 7 roles + 7 (M) + 1 (N on R0) = 15
    assert checked.source(error) == "N" and "'N@R0'" in error.message
    assert checked.line(error) == 11
    ok = check(text.replace("self.assumeRole(N, { });", ""))
    assert ok.with_code("E120") == []


def test_mixin_application_command_table(check) -> None:
    commands = " ".join(f"command c{k}() {{ }}" for k in range(3))
    checked = check(f"role W {{ {commands} startup s() {{ self.assumeRole(M, {{ }}); }} }}\n"
                    "role M modifies W { command d() { } command e() { } command f() { } }\n"
                    "deployment { W }")
    [error] = checked.with_code("E121")
    assert checked.source(error) == "M" and "applied to 'W'" in error.message


def test_command_limit_counts_inherited_commands(check) -> None:
    commands = " ".join(f"command c{k}() {{ }}" for k in range(4))
    checked = check(f"abstract role W {{ {commands} }}\nrole A extends W {{ command d() {{ }} "
                    "command e() { } }\ndeployment { A }")
    [error] = checked.with_code("E121")
    assert checked.source(error) == "A" and len(error.related) == 6


def test_behaviours_take_command_table_entries(check) -> None:
    """One limit, one rule: behaviours run as user commands, so the checker counts them with the
    commands (before, only the compiler did, and only once the rest of the program was error-free)."""
    commands = " ".join(f"command c{k}() {{ }}" for k in range(4))
    checked = check(f"abstract role W {{ {commands} behavior b() {{ }} }}\n"
                    "role A extends W { behavior d() { } }\ndeployment { A }")
    [error] = checked.with_code("E121")
    assert checked.source(error) == "A" and "6 commands and behaviours" in error.message
    assert sorted(r.message for r in error.related)[:2] == ["behavior 'b'", "behavior 'd'"]
    five = check(f"role A {{ {commands} behavior b() {{ }} }}\ndeployment {{ A }}")
    assert five.with_code("E121") == []


def test_a_mixins_behaviours_take_no_entry_of_its_application(check) -> None:
    commands = " ".join(f"command c{k}() {{ }}" for k in range(4))
    checked = check(f"role W {{ {commands} startup s() {{ self.assumeRole(M, {{ }}); }} }}\n"
                    "role M modifies W { command d() { } behavior e() { } behavior f() { } }\n"
                    "deployment { W }")
    assert checked.with_code("E121") == []


def test_lattice_parity_rules_out_witnesses(check) -> None:
    checked = check("role A { self.y() == 1; }\nrole B { self.center_position == NORTH_SOUTH; }\n"
                    "deployment { A, B }")
    assert checked.diagnostics == [], checked.summary()
    checked = check("role A { self.y() == 1; }\nrole B { self.center_position == UP_DOWN; }\n"
                    "deployment { A, B }")
    [warning] = checked.with_code("W503")
    assert "axis UP_DOWN" in warning.message and "y = 1" in warning.message
