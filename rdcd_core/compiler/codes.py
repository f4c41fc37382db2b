"""The diagnostic codes of the compiler: E6xx / W6xx, limits of the DCD-VM target (docs/language.md).

E604, E606 and E607 are backstops: the checker reports those programs first (E2xx-E4xx). E602 is
retired. E604 was the error of a number known only at run time (a speed, an angle, turns); since
issue 25 every number may be one, and only directions, events and roles must be constants: values
of those types are always constants, so the checker's E303 comes first.
"""

from __future__ import annotations

from rdcd_core.diagnostics import Severity, define_code

_E, _W = Severity.ERROR, Severity.WARNING


def _leds(count: int) -> str:
    return " ".join(f"self.setLed({i});" for i in range(count))


FRAGMENT_TOO_LARGE = define_code(
    "E601", _E, "a compiled fragment exceeds 64 program bytes",
    "role A { self.x() > 0;\n"
    f"  startup s() {{ if (connected_role(UP, A) > 0) {{ {_leds(30)} }} }} }}\ndeployment {{ A }}")
# E602 (more than 14 role identifiers) is retired: the checker's E120 counts the same identifiers
# and reported every such program first (docs/diagnostics.md, "Retired codes").
TOO_MANY_COMMANDS = define_code(
    "E603", _E, "a command gets no number in its role's command table (a command keeps one number "
    "in every role that has it)",
    "role A { self.x() > 0; command a() { } command b() { } command c() { } command d() { }\n"
    "  command e() { } }\nrole B { self.x() < 0; command a() { } command f() { } }\n"
    "role C { self.x() == 0; command b() { } command c() { } command d() { } command e() { }\n"
    "  command f() { } }\ndeployment { A, B, C }")
NOT_CONSTANT = define_code(
    "E604", _E, "the target needs a compile-time constant here (a direction, an event or a role)",
    "role A { self.x() > 0; command c(e) { self.disableEvent(e); } }\ndeployment { A }")
EXT_REFUSED = define_code(
    "E605", _E, "code needs an instruction the target does not run (e.g. --target original)",
    "// rdcd check --target original\nrole A { self.x() + self.y() > 0; }\ndeployment { A }")
UNSUPPORTED = define_code(
    "E606", _E, "construct not supported by the DCD-VM code generator",
    "role A { self.x() > 0; startup s() { self.s(); } }\ndeployment { A }")
VERIFIER_REJECTED = define_code(
    "E607", _E, "internal: a compiled fragment was rejected by the verifier",
    "role A { self.x() > 0; }\ndeployment { A }")
TARGET_LIMIT = define_code(
    "E608", _E, "a run of a fragment exceeds the target's operand stack or instructions per run",
    "role A { self.x() > " + "(self.y() + " * 16 + "self.y()" + ")" * 16 + "; }\ndeployment { A }")
OVER_BUDGET = define_code(
    "W601", _W, "a fragment exceeds the packet budget and could not be split",
    f"role A {{ self.x() > 0;\n  startup s() {{ if (connected_role(UP, A) > 0) {{ {_leds(19)} }} }} }}\n"
    "deployment { A }")
TOO_MANY_PROGRAMS = define_code(
    "W602", _W, "more than 10 programs stored at once on one module",
    "role A { self.x() > 0;\n  startup s() { "
    + " ".join(f"self.handleEvent(EVENT_PROXIMITY_{k}, {{ self.setLed(1); }});" for k in range(8))
    + " }\n" + "".join(f"  command c{i}() {{ self.setLed({i}); }}\n" for i in range(3))
    + "}\ndeployment { A }")
MIXIN_METHOD_IGNORED = define_code(
    "W603", _W, "a mixin's startup or behaviour method is not compiled",
    "role W { self.y() > 0; }\nrole M modifies W { startup s() { self.sleep(); } }\ndeployment { W }")
HANDLER_REFIRES = define_code(
    "W604", _W, "a handler that does not first disable its event runs again on every step while its "
                "sensor sees an object (original target)",
    "// rdcd check --target original\n"
    "role A { self.x() > 0;\n  startup s() { self.handleEvent(EVENT_PROXIMITY_0, { self.setLed(1); }); } }\n"
    "deployment { A }")
HANDLER_MISSED = define_code(
    "W605", _W, "an event handler can miss an object while a behaviour of its module sleeps (original "
                "target: sensors are looked at only between tasks)",
    "// rdcd check --target original\n"
    "role A { self.x() > 0;\n"
    "  startup s() { self.handleEvent(EVENT_PROXIMITY_0, { self.disableEvent(EVENT_PROXIMITY_0); }); }\n"
    "  behavior b() { self.sleep(); } }\n"
    "deployment { A }")
EARLY_COMMAND = define_code(
    "W606", _W, "a startup sends a command before the fragment that installs the command's code, and "
                "the target drops it (original target; the default target holds it until the code is there)",
    "// rdcd check --target original\n"
    "role A { self.x() > 0; startup s() { B.go(); } }\n"
    "role B { self.x() < 0; command go() { self.setLed(1); } }\n"
    "deployment { A, B }")
