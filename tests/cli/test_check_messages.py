"""`rdcd check` as a real process: where its messages point and what they say (issue 10)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT


def check(path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "rdcd_core", "check", str(path)], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


def test_missing_semicolon_points_at_the_end_of_its_line(tmp_path: Path) -> None:
    path = tmp_path / "semi.rdcd"
    path.write_text("role A {\n  startup go() {\n    self.sleep()\n    self.stopTurning();\n  }\n}\n"
                    "deployment { A }\n", encoding="utf-8")
    done = check(path)
    assert done.returncode == 1, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == f"{path}:3:17: error[E004]: expected ';' after the call, found keyword 'self'"
    assert lines[2] == "3 |     self.sleep()"
    assert lines[3] == "  |                 ^"
    assert lines[4] == "  = help: insert ';'"
    assert lines[-1] == "1 file checked: 1 error, 0 warnings"


def test_missing_parenthesis_points_where_it_belongs(tmp_path: Path) -> None:
    path = tmp_path / "paren.rdcd"
    path.write_text("role A {\n  startup go() {\n    if (self.y() > 0\n      self.sleep();\n  }\n}\n"
                    "deployment { A }\n", encoding="utf-8")
    done = check(path)
    assert done.returncode == 1
    first = done.stdout.splitlines()[0]
    assert first == (f"{path}:3:21: error[E012]: expected ')' to close the 'if' condition opened on line 3, "
                     "found keyword 'self'")


def _sum_program(tmp_path: Path, name: str, terms: list[str]) -> Path:
    path = tmp_path / name
    condition = " + ".join(terms) + " > 0"
    path.write_text(f"role A {{\n  startup go() {{\n    if ({condition}) self.sleep();\n  }}\n}}\n"
                    "deployment { A }\n", encoding="utf-8")
    return path


def test_a_flat_sum_of_100_terms_is_not_nested_too_deep(tmp_path: Path) -> None:
    constant = check(_sum_program(tmp_path, "constant.rdcd", ["1", "-1"] * 50))
    assert constant.returncode == 0, constant.stdout + constant.stderr
    assert constant.stdout.strip() == "1 file checked: no problems"
    queries = check(_sum_program(tmp_path, "queries.rdcd", ["self.y()"] * 100))
    assert queries.returncode == 1
    assert "nested" not in queries.stdout and "E015" not in queries.stdout
    # the real limit: the code of 100 additions does not fit a program slot of the target
    assert "error[E601]: fragment A_startup is" in queries.stdout
    assert "more than the 64 bytes of a program slot" in queries.stdout


def test_a_very_long_chain_gets_its_real_limit(tmp_path: Path) -> None:
    done = check(_sum_program(tmp_path, "long.rdcd", ["self.y()"] * 5000))
    assert done.returncode == 1
    first = done.stdout.splitlines()[0]
    assert "error[E016]: this has more than 300 operations one inside another" in first
    assert "nested" not in first and "internal error" not in done.stdout


def test_conflict_witnesses_follow_the_vms_saturating_arithmetic(tmp_path: Path) -> None:
    b = "role B { self.x() >= 90; self.y() >= 90; }"
    never = tmp_path / "never.rdcd"  # x + y would wrap to a negative; saturated it is 127 there
    never.write_text(f"role A {{ self.x() + self.y() < 0; }}\n{b}\ndeployment {{ A, B }}\n", encoding="utf-8")
    done = check(never)
    assert done.returncode == 0 and "W503" not in done.stdout, done.stdout
    saturates = tmp_path / "saturates.rdcd"
    saturates.write_text(f"role A {{ self.x() + self.y() > 0; }}\n{b}\ndeployment {{ A, B }}\n",
                         encoding="utf-8")
    done = check(saturates)
    assert "warning[W503]: 'B' and 'A' can both hold on one module (e.g. x = 90, y = 90)" in done.stdout



def test_behaviours_count_in_the_command_table_at_check_time(tmp_path: Path) -> None:
    path = tmp_path / "table.rdcd"
    path.write_text("role A {\n  command a() { } command b() { } command c() { } command d() { }\n"
                    "  behavior e() { } behavior f() { }\n  startup s() { self.nope(); }\n}\n"
                    "deployment { A }\n", encoding="utf-8")
    done = check(path)
    assert done.returncode == 1
    # reported with the other errors, not only once they are fixed (the compiler's E603 before)
    assert "error[E121]: role 'A' has 6 commands and behaviours" in done.stdout
    assert "E603" not in done.stdout and "E30" in done.stdout


def test_retired_codes_are_documented() -> None:
    done = subprocess.run([sys.executable, "-m", "rdcd_core.diagnostics_doc"], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0
    retired = done.stdout.split("## Retired codes")[1]
    assert "### E602" in retired and "E120" in retired
    assert "[E602]" not in done.stdout.split("## Retired codes")[0]


def test_a_long_else_if_chain_is_not_nested_too_deep(tmp_path: Path) -> None:
    path = tmp_path / "elif.rdcd"
    chain = "\n    else ".join(f"if (self.y() == {k}) self.setLed({k});" for k in range(120))
    text = f"role A {{\n  self.x() > 0;\n  startup go() {{\n    {chain}\n  }}\n}}\ndeployment {{ A }}\n"
    path.write_text(text, encoding="utf-8")
    done = check(path)
    assert "E015" not in done.stdout and "nested" not in done.stdout, done.stdout[:500]
    assert "error[E601]: fragment A_startup is" in done.stdout  # the target's real limit
