"""The diagnostic codes of the semantic analysis (docs/language.md).

E1xx roles and hierarchy, E2xx names and types, E3xx methods, calls and blocks, E4xx assumeRole,
E5xx deployment and discovery; W1xx..W5xx the warnings of the same groups.
"""

from __future__ import annotations

from rdcd_core.diagnostics import Severity, define_code

_E, _W = Severity.ERROR, Severity.WARNING

# ----------------------------------------------------------------------------- E1xx roles
INTERNAL_ERROR = define_code(
    "E100", _E, "internal error of the checker",
    "(no program triggers it: it reports a bug in rdcd instead of a traceback)")
DUPLICATE_ROLE = define_code(
    "E101", _E, "duplicate role name",
    "role A { }\nrole A { }\ndeployment { A }")
UNKNOWN_SUPER = define_code(
    "E102", _E, "unknown super-role",
    "role A extends Whel { }\ndeployment { A }")
INHERITANCE_CYCLE = define_code(
    "E103", _E, "inheritance cycle",
    "role A extends B { }\nrole B extends A { }\ndeployment { }")
EXTENDS_MIXIN = define_code(
    "E104", _E, "a role cannot extend a mixin",
    "role W { }\nrole M modifies W { }\nrole A extends M { }\ndeployment { W, A }")
UNKNOWN_MODIFIED = define_code(
    "E105", _E, "a mixin modifies an unknown role",
    "role M modifies Whel { }\ndeployment { }")
ABSTRACT_MIXIN = define_code(
    "E106", _E, "a mixin cannot be abstract",
    "role W { }\nabstract role M modifies W { }\ndeployment { W }")
MIXIN_INVARIANT = define_code(
    "E107", _E, "a mixin cannot have invariants",
    "role W { }\nrole M modifies W { self.y() > 0; }\ndeployment { W }")
MODIFIES_MIXIN = define_code(
    "E108", _E, "a mixin cannot modify another mixin",
    "role W { }\nrole M modifies W { }\nrole N modifies M { }\ndeployment { W }")
DUPLICATE_MEMBER = define_code(
    "E109", _E, "duplicate member name in one role",
    "role A { constant k := 1; constant k := 2; }\ndeployment { A }")
MISSING_DEFINITIONS = define_code(
    "E110", _E, "a non-abstract role lacks definitions of abstract members",
    "abstract role W { abstract constant speed; }\nrole R extends W { }\ndeployment { R }")
OVERRIDE_KIND = define_code(
    "E111", _E, "an overriding method changes the method kind",
    "abstract role W { startup go() { } }\nrole R extends W { behavior go() { } }\n"
    "deployment { R }")
BAD_MODIFIERS = define_code(
    "E112", _E, "conflicting method modifiers",
    "role A { startup behavior go() { } }\ndeployment { A }")
ABSTRACT_WITH_BODY = define_code(
    "E113", _E, "an abstract method has a body",
    "abstract role A { abstract startup go() { self.sleep(); } }\nrole B extends A { }\n"
    "deployment { B }")
REDEFINES_MODULE = define_code(
    "E114", _E, "the predefined root role Module cannot be declared",
    "role Module { }\ndeployment { }")
TOO_MANY_ROLE_IDS = define_code(
    "E120", _E, "more than 14 role identifiers after mixin expansion",
    "".join(f"role R{k} {{ self.x() == {k}; }}\n" for k in range(1, 16))
    + "deployment { " + ", ".join(f"R{k}" for k in range(1, 16)) + " }")
TOO_MANY_COMMANDS = define_code(
    "E121", _E, "more than 5 entries in one role's command table (commands and behaviours)",
    "role A { command a() { } command b() { } command c() { } command d() { }\n"
    "  behavior e() { } behavior f() { } }\ndeployment { A }")

# ----------------------------------------------------------------------------- E2xx names, types
UNKNOWN_NAME = define_code(
    "E201", _E, "unknown name",
    "role A { self.center_position == EAST_WST; }\ndeployment { A }")
TYPE_MISMATCH = define_code(
    "E202", _E, "operand types do not fit the operator",
    "role A { self.y() + EAST > 0; }\ndeployment { A }")
NOT_BOOL = define_code(
    "E203", _E, "an invariant or condition is not bool",
    "role A { self.y(); }\ndeployment { A }")
INT_RANGE = define_code(
    "E204", _E, "integer outside -128..127",
    "role A { constant k := 200; }\ndeployment { A }")
NOT_CONSTANT = define_code(
    "E205", _E, "a constant definition is not constant-foldable",
    "role A { constant k := self.y(); }\ndeployment { A }")
CONSTANT_TYPE = define_code(
    "E206", _E, "a constant must be an int, axis, dir or event",
    "role A { constant k := 1 > 0; }\ndeployment { A }")
CONSTANT_TYPE_DISAGREES = define_code(
    "E207", _E, "definitions of one constant disagree in type across the hierarchy",
    "abstract role W { abstract constant d; }\nrole A extends W { constant d := EAST; }\n"
    "role B extends W { constant d := 1; }\ndeployment { A, B }")
UNKNOWN_ROLE = define_code(
    "E208", _E, "unknown role name",
    "role A { sizeof(connected_role(DOWN, Whel)) > 0; }\ndeployment { A }")
CONSTANT_CYCLE = define_code(
    "E209", _E, "a constant is defined in terms of itself",
    "role A { constant a := b; constant b := a; }\ndeployment { A }")
BAD_ANGLE = define_code(
    "E210", _E, "a joint angle is not a multiple of 10 in range",
    "role A { startup s() { self.turnTowards(35); } }\ndeployment { A }")
CONNECTOR_NEVER_LATCHES = define_code(
    "E220", _E, "a connector argument that can never latch",
    "role A { startup s() { self.connect(3); } }\ndeployment { A }")

# ----------------------------------------------------------------------------- E3xx calls
UNKNOWN_METHOD = define_code(
    "E301", _E, "unknown primitive or method",
    "role A { startup s() { self.turnContinuosly(1); } }\ndeployment { A }")
ARG_COUNT = define_code(
    "E302", _E, "wrong number of arguments",
    "role A { startup s() { self.turnContinuously(); } }\ndeployment { A }")
ARG_TYPE = define_code(
    "E303", _E, "wrong argument type",
    "role A { startup s() { self.turnContinuously(EAST); } }\ndeployment { A }")
BLOCK_NOT_ALLOWED = define_code(
    "E304", _E, "a block is allowed only as the second argument of handleEvent or assumeRole",
    "role A { startup s() { self.setLed({ self.sleep(); }); } }\ndeployment { A }")
RECURSION = define_code(
    "E305", _E, "recursive plain methods",
    "role A { f() { self.g(); } g() { self.f(); } startup s() { self.f(); } }\n"
    "deployment { A }")
BAD_GLOBAL_CALL = define_code(
    "E306", _E, "Role.name() does not name a command of that role",
    "role A { startup s() { A.go(); } go() { } }\ndeployment { A }")
NOT_PLAIN = define_code(
    "E307", _E, "only plain methods can be called locally with self.name()",
    "role A { command c() { } startup s() { self.c(); } }\ndeployment { A }")
VOID_VALUE = define_code(
    "E308", _E, "a call without a value is used in an expression",
    "role A { startup s() { if (self.sleep()) self.sleep(); } }\ndeployment { A }")
UNKNOWN_FUNCTION = define_code(
    "E309", _E, "unknown function",
    "role A { size(self.total_connected()) > 0; }\ndeployment { A }")
MISSING_PARENS = define_code(
    "E310", _E, "only zero-argument queries may omit the parentheses",
    "role A { startup s() { self.sleep; } }\ndeployment { A }")
ACTION_IN_EXPRESSION = define_code(
    "E320", _E, "a connector or joint action inside an expression",
    "role A { self.connect(0); }\ndeployment { A }")
UNUSED_VALUE = define_code(
    "W301", _W, "the value of a query is unused",
    "role A { startup s() { self.y(); } }\ndeployment { A }")

# ----------------------------------------------------------------------------- E4xx assumeRole
NOT_A_MIXIN = define_code(
    "E401", _E, "assumeRole needs a mixin role",
    "role W { startup s() { self.assumeRole(W, { }); } }\ndeployment { W }")
MIXIN_NOT_APPLICABLE = define_code(
    "E402", _E, "the mixin does not modify the role that owns the method",
    "role W { }\nrole M modifies W { }\nrole A { startup s() { self.assumeRole(M, { }); } }\n"
    "deployment { W, A }")
NESTED_ASSUME = define_code(
    "E403", _E, "the same mixin is assumed again inside its own assumeRole block",
    "role W { startup s() { self.assumeRole(M, { self.assumeRole(M, { }); }); } }\n"
    "role M modifies W { }\ndeployment { W }")
HANDLER_IN_ASSUME = define_code(
    "W401", _W, "an event handler installed inside assumeRole runs later, in another role",
    "role W { startup s() { self.assumeRole(M, {\n"
    "  self.handleEvent(EVENT_PROXIMITY_0, { self.sleep(); }); }); } }\n"
    "role M modifies W { }\ndeployment { W }")

# ----------------------------------------------------------------------------- E5xx deployment
UNKNOWN_DEPLOYED = define_code(
    "E501", _E, "unknown role in the deployment",
    "role Axle { }\ndeployment { Axel }")
ABSTRACT_DEPLOYED = define_code(
    "E502", _E, "an abstract role cannot be deployed",
    "abstract role W { }\nrole R extends W { }\ndeployment { W, R }")
MIXIN_DEPLOYED = define_code(
    "E503", _E, "a mixin cannot be deployed",
    "role W { }\nrole M modifies W { }\ndeployment { W, M }")
REPEATED_DEPLOYED = define_code(
    "E504", _E, "a role is deployed twice",
    "role A { }\ndeployment { A, A }")
DISCOVERY_ORDER = define_code(
    "W501", _W, "a role is discovered before a role its invariants observe",
    "role Axle { sizeof(connected_role(DOWN, Wheel)) > 0; }\n"
    "role Wheel { self.center_position == EAST_WEST; }\ndeployment { Axle, Wheel }")
DISCOVERY_CYCLE = define_code(
    "W502", _W, "roles observe each other in a cycle: no discovery order satisfies both",
    "role A { sizeof(connected_role(UP, B)) > 0; }\n"
    "role B { sizeof(connected_role(DOWN, A)) > 0; }\ndeployment { A, B }")
ROLE_CONFLICT = define_code(
    "W503", _W, "two deployed roles can hold on the same module: it takes the first deployed",
    "role A { self.y() > 0; }\nrole B { self.center_position == EAST_WEST; }\n"
    "deployment { A, B }")
NEVER_HOLDS = define_code(
    "W505", _W, "a deployed role's invariants can never all hold",
    "role A { sizeof(self.total_connected()) == 1;\n  sizeof(self.connected(UP)) == 1;\n"
    "  sizeof(self.connected(DOWN)) == 1; }\ndeployment { A }")
DEAD_ROLE = define_code(
    "W504", _W, "a role is never deployed nor used",
    "role A { }\nrole Unused { }\ndeployment { A }")

# ----------------------------------------------------------------------------- E7xx state
NOT_A_STATE = define_code(
    "E701", _E, "an assignment to a name that is not a state",
    "role A { constant k := 1; startup s() { k := 2; } }\ndeployment { A }")
UNKNOWN_STATE = define_code(
    "E702", _E, "an assignment to an unknown state",
    "role A { startup s() { hops := 1; } }\ndeployment { A }")
OTHER_ROLES_STATE = define_code(
    "E703", _E, "role state used outside the role that declares it (and its sub-roles)",
    "role A { state seen := 0; }\nrole B { startup s() { seen := 1; } }\ndeployment { A, B }")
DUPLICATE_STATE = define_code(
    "E704", _E, "module state declared twice",
    "state hops := 0;\nstate hops := 1;\nrole A { }\ndeployment { A }")
BAD_INITIAL_VALUE = define_code(
    "E705", _E, "the initial value of a state is not a constant int",
    "state hops := self.z();\nrole A { }\ndeployment { A }")
NOT_PUBLISHED = define_code(
    "E706", _E, "neighbours' values of something that is not module state",
    "role A { state seen := 0; startup s() { seen := count(neighbours.seen); } }\ndeployment { A }")
VALUES_OUT_OF_PLACE = define_code(
    "E707", _E, "neighbours' values are used other than as the argument of min, max, count or sum",
    "state hops := 0;\nrole A { startup s() { hops := neighbours.hops; } }\ndeployment { A }")
BAD_NEIGHBOUR_FILTER = define_code(
    "E708", _E, "neighbours(...) takes a direction or a connector number 0..7",
    "state hops := 0;\nrole A { startup s() { hops := sum(neighbours(9).hops); } }\ndeployment { A }")
MIXIN_STATE = define_code(
    "E709", _E, "a mixin cannot declare state (it plays on its base role's state)",
    "role W { }\nrole M modifies W { state n := 0; }\ndeployment { W }")
BAD_PARAMETER = define_code(
    "E710", _E,
    "a parameter that is not a single new name, or more parameters than the method kind takes",
    "role A { command go(a, b) { } }\ndeployment { A }")
ASSIGN_OUTSIDE_METHOD = define_code(
    "E711", _E, "an assignment directly in a role: only methods assign, invariants only read",
    "state s := 0;\nrole A { s := 1; }\ndeployment { A }")
BAD_TRAVELLING = define_code(
    "E712", _E, "a travelling state in a role, or more than one travelling state",
    "role A { travelling state hop := 0; }\ndeployment { A }")
STATE_TOO_MANY = define_code(
    "E720", _E,
    "more than 8 module states read by neighbours, or more than 24 others (the VM's 32 bytes of state)",
    "".join(f"state s{k} := 0;\n" for k in range(25)) + "role A { }\ndeployment { A }")
SHADOWS = define_code(
    "W701", _W, "a name hides a state, constant or parameter of the same name",
    "state speed := 1;\nrole A { state speed := 2; }\ndeployment { A }")
UNUSED_STATE = define_code(
    "W702", _W, "a state is never read",
    "state hops := 0;\nrole A { startup s() { hops := 1; } }\ndeployment { A }")
