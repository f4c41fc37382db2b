"""Programs that are large in one direction (issue 10, "hangs and cliffs"): many invariants, many
statements in one method, many roles. Shared by the regression tests and the scripts in
benchmarks/ (``cliffs.py``, ``inlay_hints.py``, ``hover_during_check.py``)."""

from __future__ import annotations

INVARIANTS = ("self.x() != {a};", "sizeof(self.connected(UP)) == 1;", "self.y() > {b};",
              "self.center_position == EAST_WEST;", "sizeof(self.connected(DOWN)) + {c} != 99;")
METHOD_KINDS = ("startup", "command", "behavior")


def many_invariants(count: int) -> str:
    """One role with ``count`` invariants: local ones (decided over the state space) and others."""
    lines = ["role Big {"]
    for i in range(count):
        pattern = INVARIANTS[i % len(INVARIANTS)]
        lines.append("  " + pattern.format(a=i % 200 - 100, b=i % 100 - 120, c=i % 50))
    lines += ["}", "deployment { Big }"]
    return "\n".join(lines) + "\n"


def many_ifs(count: int, kind: str = "behavior", with_else: bool = True) -> str:
    """One method of ``kind`` with ``count`` if statements (if/else: every branch ends alike)."""
    lines = ["role Big {", "  self.x() == 0;", f"  {kind} go() {{"]
    for i in range(count):
        otherwise = f" else self.setLed({(i + 1) % 8});" if with_else else ""
        lines.append(f"    if (self.y() > {i % 50}) self.setLed({i % 8});{otherwise}")
    lines += ["  }", "}", "deployment { Big }"]
    return "\n".join(lines) + "\n"


def many_roles(count: int, deployed: int = 2) -> str:
    """``count`` roles with a startup method each; the first ``deployed`` are deployed."""
    parts = [f"role R{i} {{\n  self.x() == {i % 100};\n  startup go() {{ self.setLed({i % 8}); }}\n}}\n"
             for i in range(count)]
    return "".join(parts) + "deployment { " + ", ".join(f"R{i}" for i in range(deployed)) + " }\n"


def many_subroles(count: int) -> str:
    """``count`` concrete roles extending one abstract role with a command; two deployed."""
    parts = ["abstract role W {\n  abstract constant k;\n  self.center_position == EAST_WEST;\n"
             "  startup go() { self.setLed(k); }\n  command stop() { self.setLed(0); }\n}\n"]
    parts += [f"role R{i} extends W {{\n  constant k := {i % 8};\n  self.x() == {i % 100};\n"
              f"  command c{i}() {{ self.setLed(1); }}\n}}\n" for i in range(count)]
    return "".join(parts) + "deployment { R0, R1 }\n"


def many_errors(count: int) -> str:
    """A startup method whose ``count`` calls each get the compiler's error E604 (not constant)."""
    calls = "".join(f"    self.setLed(self.y() + {i % 50});\n" for i in range(count))
    return "role Big {\n  self.x() == 0;\n  startup go() {\n" + calls + "  }\n}\ndeployment { Big }\n"
