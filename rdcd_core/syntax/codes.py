"""Syntax diagnostic codes (E0xx), each with a small program that triggers it."""

from __future__ import annotations

from rdcd_core.diagnostics import Severity, define_code

E = Severity.ERROR

E_BAD_CHARACTER = define_code(
    "E001", E, "unexpected character", "role A { self.x() = 1; }\ndeployment { A }")
E_UNTERMINATED_COMMENT = define_code(
    "E002", E, "unterminated block comment", "role A { } /* no end\ndeployment { A }")
E_UNEXPECTED_TOKEN = define_code(
    "E003", E, "unexpected token", "role A { self.x() > > 1; }\ndeployment { A }")
E_MISSING_SEMICOLON = define_code(
    "E004", E, "missing ';'", "role A {\n  self.x() > 0\n}\ndeployment { A }")
E_UNMATCHED_CLOSE = define_code(
    "E005", E, "unmatched closing bracket", "role A { }\n}\ndeployment { A }")
E_UNEXPECTED_EOF = define_code(
    "E006", E, "unexpected end of file", "role A {\n  self.x() > 0;\n")
E_EXPECTED_NAME = define_code(
    "E007", E, "expected a name", "role A extends { }\ndeployment { A }")
E_MISSING_DEPLOYMENT = define_code(
    "E008", E, "missing deployment", "role A { self.x() > 0; }")
E_OUTSIDE_ROLE = define_code(
    "E009", E, "code outside of a role", "role A { }\nself.sleep();\ndeployment { A }")
E_MISSING_BODY = define_code(
    "E010", E, "method without a body is not abstract",
    "role A { startup go(); }\ndeployment { A }")
E_CHAINED_COMPARISON = define_code(
    "E011", E, "comparisons cannot be chained", "role A { 0 < self.x() < 5; }\ndeployment { A }")
E_MISSING_CLOSE = define_code(
    "E012", E, "missing closing bracket", "role A { sizeof(self.total_connected() > 0; }\ndeployment { A }")
E_ELSE_WITHOUT_IF = define_code(
    "E013", E, "'else' without 'if'", "role A { startup go() { ; else ; } }\ndeployment { A }")
E_AFTER_DEPLOYMENT = define_code(
    "E014", E, "role after the deployment", "deployment { A }\nrole A { }")
E_TOO_DEEP = define_code(
    "E015", E, "nested too deeply", "role A { " + "(" * 101 + "1" + ")" * 101 + " > 0; }\ndeployment { A }")
E_TOO_LONG = define_code(
    "E016", E, "expression too long", "role A { " + "+".join(["1"] * 302) + " > 0; }\ndeployment { A }")
