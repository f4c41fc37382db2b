"""One invalid program per static rule of docs/language.md: code, severity, line and range."""

from __future__ import annotations

import pytest

from rdcd_core.diagnostics import Severity, code_info

WHEEL = """abstract role Wheel {
  abstract constant dir, speed;
  self.center_position == EAST_WEST;
  startup go() { self.turnContinuously(speed); }
}
"""

# (code, line, text of the reported range, program)
CASES: list[tuple[str, int, str, str]] = [
    # ---- roles and hierarchy
    ("E101", 2, "A", "role A { }\nrole A { }\ndeployment { A }"),
    ("E102", 1, "Whel", "role A extends Whel { }\ndeployment { A }"),
    ("E103", 1, "B", "role A extends B { }\nrole B extends A { }\ndeployment { }"),
    ("E103", 2, "A", "role A extends B { }\nrole B extends A { }\ndeployment { }"),
    ("E104", 3, "M", "role W { }\nrole M modifies W { }\nrole A extends M { }\ndeployment { W, A }"),
    ("E105", 1, "Whel", "role M modifies Whel { }\ndeployment { }"),
    ("E106", 2, "abstract", "role W { }\nabstract role M modifies W { }\ndeployment { W }"),
    ("E107", 3, "self.y() > 0;", "role W { }\nrole M modifies W {\n self.y() > 0; }\ndeployment { W }"),
    ("E108", 3, "M", "role W { }\nrole M modifies W { }\nrole N modifies M { }\ndeployment { W }"),
    ("E109", 2, "k", "role A { constant k := 1;\n constant k := 2; }\ndeployment { A }"),
    ("E109", 2, "go", "role A { startup go() { }\n behavior go() { } }\ndeployment { A }"),
    ("E109", 1, "sleep", "role A { sleep() { } }\ndeployment { A }"),
    ("E110", 6, "Right", WHEEL + "role Right extends Wheel { constant dir := EAST; }\n"
     "deployment { Right }"),
    ("E110", 2, "R", "abstract role W { abstract go(); }\nrole R extends W { }\ndeployment { R }"),
    ("E111", 2, "go", "abstract role W { startup go() { } }\n"
     "role R extends W { behavior go() { } }\ndeployment { R }"),
    ("E112", 1, "behavior", "role A { startup behavior go() { } }\ndeployment { A }"),
    ("E113", 1, "abstract", "abstract role A { abstract startup go() { self.sleep(); } }\n"
     "role B extends A { }\ndeployment { B }"),
    ("E114", 1, "Module", "role Module { }\ndeployment { }"),
    ("E121", 1, "A", "role A { command a() { } command b() { } command c() { } command d() { }\n"
     "  command e() { } command f() { } }\ndeployment { A }"),
    # ---- names and types
    ("E201", 1, "EAST_WST", "role A { self.center_position == EAST_WST; }\ndeployment { A }"),
    ("E201", 2, "spede", "role A { constant speed := 1;\n startup s() { self.turnContinuously(spede); } }"
     "\ndeployment { A }"),
    ("E202", 1, "+", "role A { self.y() + EAST > 0; }\ndeployment { A }"),
    ("E202", 1, "==", "role A { self.center_position == EAST; }\ndeployment { A }"),
    ("E202", 1, "<", "role A { self.center_position < 3; }\ndeployment { A }"),
    ("E202", 1, "&&", "role A { self.y() > 0 && 1; }\ndeployment { A }"),
    ("E202", 1, "!self.y()", "role A { !self.y(); }\ndeployment { A }"),
    ("E202", 1, "Axle", "role Axle { self.y() == Axle; }\ndeployment { Axle }"),
    ("E203", 1, "self.y()", "role A { self.y(); }\ndeployment { A }"),
    ("E203", 1, "self.x()", "role A { startup s() { if (self.x()) self.sleep(); } }\ndeployment { A }"),
    ("E204", 1, "200", "role A { constant k := 200; }\ndeployment { A }"),
    ("E204", 1, "100 + 100", "role A { constant k := 100 + 100; }\ndeployment { A }"),
    ("E204", 1, "-k", "role A { constant k := -128;\nstartup s() { self.setLed(-k); } }\ndeployment { A }"
     .replace("\nstartup", " startup")),
    ("E204", 1, "129", "role A { constant k := -129; }\ndeployment { A }"),
    ("E205", 1, "self.y()", "role A { constant k := self.y(); }\ndeployment { A }"),
    ("E205", 1, "sizeof(self.total_connected())",
     "role A { constant k := sizeof(self.total_connected()); }\ndeployment { A }"),
    ("E206", 1, "1 > 0", "role A { constant k := 1 > 0; }\ndeployment { A }"),
    ("E207", 3, "1", "abstract role W { abstract constant d; }\nrole A extends W { constant d := EAST; }\n"
     "role B extends W { constant d := 1; }\ndeployment { A, B }"),
    ("E207", 2, "1", "role A { constant d := EAST; }\nrole B extends A { constant d := 1; }\n"
     "deployment { B }"),
    ("E208", 1, "Whel", "role A { sizeof(connected_role(DOWN, Whel)) > 0; }\ndeployment { A }"),
    ("E208", 1, "B", "role A { startup s() { B.go(); } }\ndeployment { A }"),
    ("E209", 1, "a", "role A { constant a := b; constant b := a; }\ndeployment { A }"),
    ("E210", 1, "35", "role A { startup s() { self.turnTowards(35); } }\ndeployment { A }"),
    ("E210", 2, "k", "role A { constant k := 5;\n startup s() { self.turnDegrees(k); } }\ndeployment { A }"),
    ("E211", 1, "-128", "role A { startup s() { self.turnContinuously(-128); } }\ndeployment { A }"),
    ("E211", 2, "n",
     "role A { constant n := -1;\n startup s() { self.sleepWhileTurning(n); } }\ndeployment { A }"),
    ("E212", 2, "0", "state a := 5;\nrole A { startup s() { a := a / 0; } }\ndeployment { A }"),
    ("E212", 1, "(k - 2)", "role A { constant k := 2; self.x() % (k - 2) > 0; }\ndeployment { A }"),
    ("E220", 1, "3", "role A { startup s() { self.connect(3); } }\ndeployment { A }"),
    ("E320", 1, "self.connect(0)", "role A { self.connect(0); }\ndeployment { A }"),
    # ---- methods, calls, blocks
    ("E301", 1, "turnContinuosly", "role A { startup s() { self.turnContinuosly(1); } }\ndeployment { A }"),
    ("E301", 2, "hepl", "role A { help() { }\n startup s() { self.hepl(); } }\ndeployment { A }"),
    ("E302", 1, "self.turnContinuously()", "role A { startup s() { self.turnContinuously(); } }\n"
     "deployment { A }"),
    ("E302", 1, "sizeof(self.total_connected(), 1)",
     "role A { sizeof(self.total_connected(), 1) > 0; }\ndeployment { A }"),
    ("E302", 1, "self.f(1)", "role A { f() { } startup s() { self.f(1); } }\ndeployment { A }"),
    ("E302", 1, "A.c(1)", "role A { command c() { } startup s() { A.c(1); } }\ndeployment { A }"),
    ("E303", 1, "EAST", "role A { startup s() { self.turnContinuously(EAST); } }\ndeployment { A }"),
    ("E303", 1, "self.y()", "role A { sizeof(self.y()) > 0; }\ndeployment { A }"),
    ("E303", 1, "1", "role A { sizeof(self.connected(1)) > 0; }\ndeployment { A }"),
    ("E303", 1, "3", "role A { sizeof(connected_role(DOWN, 3)) > 0; }\ndeployment { A }"),
    ("E303", 1, "1", "role A { startup s() { self.handleEvent(EVENT_PROXIMITY_0, 1); } }\n"
     "deployment { A }"),
    ("E304", 1, "{ self.sleep(); }", "role A { startup s() { self.setLed({ self.sleep(); }); } }\n"
     "deployment { A }"),
    ("E304", 1, "{ }", "role A { startup s() { A.c({ }); } command c() { } }\ndeployment { A }"),
    ("E305", 1, "f", "role A { f() { self.g(); } g() { self.f(); } startup s() { self.f(); } }\n"
     "deployment { A }"),
    ("E305", 1, "f", "role A { f() { self.f(); } startup s() { self.f(); } }\ndeployment { A }"),
    ("E306", 1, "go", "role A { startup s() { A.go(); } go() { } }\ndeployment { A }"),
    ("E306", 1, "stpo", "role A { command stop() { } startup s() { A.stpo(); } }\ndeployment { A }"),
    ("E306", 2, "stop", "role A { command stop() { } }\nrole B { startup s() { B.stop(); } }\n"
     "deployment { A, B }"),
    ("E307", 1, "c", "role A { command c() { } startup s() { self.c(); } }\ndeployment { A }"),
    ("E307", 1, "b", "role A { behavior b() { } startup s() { self.b(); } }\ndeployment { A }"),
    ("E308", 1, "self.sleep()", "role A { startup s() { if (self.sleep()) self.sleep(); } }\n"
     "deployment { A }"),
    ("E308", 1, "A.c()", "role A { command c() { } A.c() == 0; }\ndeployment { A }"),
    ("E309", 1, "size", "role A { size(self.total_connected()) > 0; }\ndeployment { A }"),
    ("E309", 1, "y", "role A { y() > 0; }\ndeployment { A }"),
    ("E310", 1, "sleep", "role A { startup s() { self.sleep; } }\ndeployment { A }"),
    ("W301", 1, "self.y()", "role A { startup s() { self.y(); } }\ndeployment { A }"),
    # ---- assumeRole
    ("E401", 1, "W", "role W { startup s() { self.assumeRole(W, { }); } }\ndeployment { W }"),
    ("E401", 1, "3", "role W { startup s() { self.assumeRole(3, { }); } }\ndeployment { W }"),
    ("E402", 3, "M", "role W { }\nrole M modifies W { }\nrole A { startup s() { self.assumeRole(M, { }); } }"
     "\ndeployment { W, A }"),
    ("E403", 1, "M", "role W { startup s() { self.assumeRole(M, { self.assumeRole(M, { }); }); } }\n"
     "role M modifies W { }\ndeployment { W }"),
    ("W401", 2, "handleEvent", "role W { startup s() { self.assumeRole(M, {\n"
     "  self.handleEvent(EVENT_PROXIMITY_0, { self.sleep(); }); }); } }\n"
     "role M modifies W { }\ndeployment { W }"),
    # ---- deployment and discovery
    ("E501", 2, "Axel", "role Axle { }\ndeployment { Axel }"),
    ("E502", 3, "W", "abstract role W { }\nrole R extends W { }\ndeployment { W, R }"),
    ("E502", 2, "Module", "role A { }\ndeployment { A, Module }"),
    ("E503", 3, "M", "role W { }\nrole M modifies W { }\ndeployment { W, M }"),
    ("E504", 3, "A", "role A { }\ndeployment { A,\n A }"),
    ("W501", 3, "Axle", "role Axle { sizeof(connected_role(DOWN, Wheel)) > 0; }\n"
     "role Wheel { self.center_position == EAST_WEST; }\ndeployment { Axle, Wheel }"),
    ("W502", 3, "A", "role A { sizeof(connected_role(UP, B)) > 0; }\n"
     "role B { sizeof(connected_role(DOWN, A)) > 0; }\ndeployment { A, B }"),
    ("W503", 3, "B", "role A { self.y() > 0; }\nrole B { self.center_position == EAST_WEST; }\n"
     "deployment { A, B }"),
    ("W504", 2, "Unused", "role A { }\nrole Unused { }\ndeployment { A }"),
    ("W505", 4, "A", "role A { sizeof(self.connected(UP)) == 1 && sizeof(self.connected(DOWN)) == 1;\n"
     "  sizeof(self.total_connected()) == 1; }\ndeployment {\n A }"),
]


@pytest.mark.parametrize(("code", "line", "text", "program"), CASES,
                         ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_rule(check, code: str, line: int, text: str, program: str) -> None:
    checked = check(program)
    found = checked.with_code(code)
    assert found, f"expected {code}, got:\n{checked.summary()}"
    matching = [d for d in found if checked.line(d) == line and checked.source(d) == text]
    assert matching, f"expected {code} at line {line} on {text!r}, got:\n" + "\n".join(
        f"{checked.line(d)} {checked.source(d)!r}" for d in found)
    info = code_info(code)
    assert info is not None
    expected = Severity.ERROR if code.startswith("E") else Severity.WARNING
    assert info.severity is expected
    assert all(d.severity is expected for d in found)
    assert all(d.message and "\n" not in d.message for d in found)


def test_every_semantic_code_is_tested() -> None:
    from rdcd_core.diagnostics import all_codes

    tested = {case[0] for case in CASES}
    semantic = {info.code for info in all_codes() if info.code[1] in "12345"}
    semantic -= {"E100", "E120"}  # internal error; the role-id limit has its own test
    assert semantic <= tested, sorted(semantic - tested)


def test_code_examples_trigger_their_code(check) -> None:
    from rdcd_core.diagnostics import all_codes

    for info in all_codes():
        if info.code[1] not in "12345" or info.code == "E100":
            continue
        checked = check(info.example)
        assert info.code in checked.codes(), f"{info.code} example:\n{checked.summary()}"
