"""The diagnostic codes of reconfiguration sequences (docs/reconfiguration.md): E80x the names
and arguments of a step, E81x what the run through the lattice model from the starting
configuration finds."""

from __future__ import annotations

from rdcd_core.diagnostics import Severity, define_code

_E, _W = Severity.ERROR, Severity.WARNING

_ROLE = "role A { self.center_position == NORTH_SOUTH; }\nrole B { }\n"

DUPLICATE_SEQUENCE = define_code(
    "E801", _E, "two sequences, or a sequence and a module state, of one name (or a state named like the "
    "sequence's own S_par, S_t, S_k, S_a)",
    _ROLE + "sequence s { A.waitUntil(1 == 1); }\nsequence s { }\ndeployment { A, B }")
UNKNOWN_STEP_ROLE = define_code(
    "E802", _E, "a step names a role that is not in the deployment",
    _ROLE + "sequence s { Wheel.connect(0); }\ndeployment { A, B }")
BAD_STEP = define_code(
    "E803", _E,
    "a step's action is not connect(c), disconnect(c), turnQuarters(n) or waitUntil(condition), "
    "or its argument is not what the action takes",
    _ROLE + "sequence s { A.connect(1); }\ndeployment { A, B }")
UNKNOWN_CONFIG = define_code(
    "E804", _E, "the starting configuration of a sequence cannot be loaded",
    _ROLE + "sequence s(car99) { A.connect(0); }\ndeployment { A, B }")
NO_HOLDER = define_code(
    "E810", _E, "no module holds the step's role (with its condition) at that point of the sequence",
    "role Wheel { self.center_position == UP_DOWN; sizeof(self.total_connected()) == 9; }\n"
    "role B { }\nsequence s(car7) { Wheel.disconnect(0); }\ndeployment { Wheel, B }")
MANY_HOLDERS = define_code(
    "E811", _E, "more than one module holds the step's role (with its condition): which one acts?",
    "role Wheel { self.center_position == EAST_WEST; }\nrole B { }\n"
    "sequence s(car7) { Wheel.turnQuarters(1); }\ndeployment { Wheel, B }")
COLLISION = define_code(
    "E812", _E, "a turn would carry a module through an occupied cell or the ground",
    "role Driver { self.center_position == NORTH_SOUTH; }\nrole B { }\n"
    "sequence s(car7) { Driver.turnQuarters(1); }\ndeployment { Driver, B }")
LOOP = define_code(
    "E813", _E, "a turn is blocked by a loop: the turning part is also held by the other side",
    "role A { self.center_position == EAST_WEST; self.x() == 1; self.y() == 1; }\nrole B { }\n"
    "sequence s(eight7) { A.turnQuarters(1); }\ndeployment { A, B }")
SPLIT = define_code(
    "E814", _E, "a disconnect would split the robot in two",
    "role Axle { self.center_position == UP_DOWN; self.y() > 0; }\nrole B { }\n"
    "sequence s(car7) { Axle.disconnect(4); }\ndeployment { Axle, B }")
NO_LATCH = define_code(
    "E815", _E,
    "a connector cannot latch or unlatch there (female, nothing aligned, in use, not latched)",
    "role Driver { self.center_position == NORTH_SOUTH; }\nrole B { }\n"
    "sequence s(car7) { Driver.connect(0); }\ndeployment { Driver, B }")
SHARED = define_code(
    "E816", _E, "steps of one parallel block touch the same module",
    "role Axle { self.center_position == UP_DOWN; self.y() > 0; }\n"
    "role Left { self.center_position == EAST_WEST; self.x() > 0; self.y() > 0; }\nrole B { }\n"
    "sequence s(car7) { parallel { Axle.waitUntil(1 == 1); Left.turnQuarters(1); "
    "Axle.turnQuarters(2); } }\ndeployment { Axle, Left, B }")
UNCHECKED = define_code(
    "W810", _W,
    "the checker cannot tell which module acts (the role or condition reads values known only at "
    "run time); the rest of the sequence is not checked",
    "state ready := 0;\nrole A { ready == max(neighbours.ready); }\nrole B { }\n"
    "sequence s(car7) { A.waitUntil(1 == 1); }\ndeployment { A, B }")
TOO_MANY_FRAGMENTS = define_code(
    "E805", _E,
    "the program with its sequences compiles to more fragments than a module has program slots",
    "role A { self.center_position == EAST_WEST; }\nrole B { self.center_position == NORTH_SOUTH; }\n"
    "role C { self.center_position == UP_DOWN; }\nsequence s {\n"
    + "  A.waitUntil(1 == 1); B.waitUntil(1 == 1); C.waitUntil(1 == 1);\n" * 4
    + "}\ndeployment { A, B, C }")

