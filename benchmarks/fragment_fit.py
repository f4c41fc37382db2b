"""Fragments that fit: per program, fragments, largest, fragments over the packet budget, before and
after splitting (commands and behaviours: rdcd_core/compiler/chain.py; handlers: handlers.py;
state-dependent discovery: watched.py).

Corpus: every example, every RDCD program of the docs (``rdcd`` code blocks of docs/*.md that
check without errors: the diagnostics page's examples included), the tutorial's steps, and the
programs of issue 25 (``ISSUE``), with programs of state-dependent roles, a large handler and a
large reactive behaviour (``STATE_ROLES``). "Before" compiles with no spare command numbers,
which is the planner before splitting (nothing is split but startup statements).

    python benchmarks/fragment_fit.py [--target default|original] [--all]

``--all`` prints every program; by default those whose fragments changed or are over the budget.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import rdcd_core.compiler as compiler  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402

_WHEEL = ("abstract role Wheel {{\n  abstract constant side;\n  state told := 0;\n"
          "  self.center_position == EAST_WEST;\n  sizeof(self.total_connected()) == 1;\n"
          "  sizeof(self.connected(side)) == 1;\n  {member}\n}}\n"
          "role RightWheel extends Wheel {{ constant side := EAST; }}\n"
          "role LeftWheel extends Wheel {{ constant side := WEST; }}\n"
          "deployment {{ RightWheel, LeftWheel }}\n")
ISSUE = {
    "issue: go(speed) wheel": _WHEEL.format(member=(
        "command go(speed) { told := told + 1; if (side == EAST) self.turnContinuously(speed); "
        "else self.turnContinuously(-speed); }")),
    "issue: behaviour of state a": (
        "state a := 1;\nrole W { self.center_position == EAST_WEST;\n"
        "  behavior b() { self.turnContinuously(a); } }\ndeployment { W }\n"),
    "chain: gait behaviour": _WHEEL.format(member=(
        "behavior b() { told := told + 1; self.setLed(told); self.turnTowards(30); self.sleep(); "
        "self.setLed(1); self.turnTowards(-30); self.sleep(); self.setLed(2); self.turnTowards(0); "
        "self.sleep(); self.setLed(3); self.turnTowards(60); self.sleep(); }")),
    "chain: show command": _WHEEL.format(member=(
        "command show(v) { self.setLed(v); self.sleep(); self.setLed(1); self.turnTowards(30); "
        "self.sleep(); self.setLed(2); self.turnTowards(-30); self.sleep(); self.setLed(3); "
        "self.turnTowards(0); self.sleep(); self.setLed(4); self.turnTowards(90); self.sleep(); "
        "self.setLed(0); told := told + v; }")),
    "chain: statement too large alone": _WHEEL.format(member=(
        "command go(speed) { told := told + 1; self.setLed(told); self.turnContinuously(speed); "
        "self.sleep(); self.setLed(0); self.turnContinuously(-speed); self.sleep(); self.stopTurning(); }")),
}
ROLE_STATE = ("state lowest := 127;\nabstract role Node {\n  behavior spread() {\n"
              "    lowest := min(min(neighbours.lowest), self.z());\n  }\n}\n"
              "role Bottom extends Node {\n  state visits := 3;\n  self.z() == lowest;\n"
              "  behavior count() { if (visits < 9) visits := visits + 1; }\n}\n"
              "role Upper extends Node { }\ndeployment { Bottom, Upper }\n")
STATE_ROLES = {
    "state: the replay's lowest/visits": ROLE_STATE,
    "state: three roles on `step == 3`-style invariants": (
        "state step := 0;\nrole Mover { step == 3; self.center_position == EAST_WEST;\n"
        "  startup go() { self.setLed(3); self.turnTowards(90); }\n"
        "  behavior b() { self.sleep(); step := step + 1; } }\n"
        "role Waiter { step < 3;\n  behavior w() { self.sleep(); self.setLed(step); step := step + 1; } }\n"
        "role Done { step > 3; startup s() { self.setLed(0); self.turnTowards(0); } }\n"
        "deployment { Mover, Waiter, Done }\n"),
    "state: six roles, one per value of `step`": (
        "state step := 0;\n" + "".join(
            f"role R{k} {{ step == {k};\n"
            f"  behavior b() {{ self.sleep(); self.setLed({k}); step := step + 1; }} }}\n"
            for k in range(6)) + "deployment { " + ", ".join(f"R{k}" for k in range(6)) + " }\n"),
    "handler of 14 statements": (
        "state hits := 0;\nrole Wheel { self.center_position == EAST_WEST;\n"
        "  startup s() { self.handleEvent(EVENT_PROXIMITY_0, { self.disableEvent(EVENT_PROXIMITY_0); "
        "hits := hits + 1; self.setLed(1); self.turnTowards(30); self.sleep(); self.setLed(2); "
        "self.turnTowards(-30); self.sleep(); self.setLed(3); self.turnTowards(0); self.sleep(); "
        "self.setLed(hits + 4); self.turnTowards(60); self.sleep(); }); }\n}\ndeployment { Wheel }\n"),
    "reactive behaviour of 8 assignments": (
        "".join(f"state {n} := 0;\n" for n in "abcd") + "role W { self.center_position == EAST_WEST;\n"
        "  behavior spread() { a := max(max(neighbours.a), self.x()); b := a + self.y(); c := b + a; "
        "d := c + b; a := min(a, 20); b := min(b, 30); c := min(c, 40); d := min(d, 50); } }\n"
        "deployment { W }\n"),
}
ISSUE.update(STATE_ROLES)
BLOCK = re.compile(r"```rdcd\n(.*?)```", re.S)


def corpus() -> dict[str, str]:
    programs: dict[str, str] = {}
    for path in sorted((ROOT / "examples").glob("*.rdcd")):
        programs[f"examples/{path.name}"] = path.read_text(encoding="utf-8")
    for path in sorted((ROOT / "docs" / "tutorial").glob("*.rdcd")):
        programs[f"docs/tutorial/{path.name}"] = path.read_text(encoding="utf-8")
    for path in sorted((ROOT / "docs").glob("*.md")):
        for n, block in enumerate(BLOCK.findall(path.read_text(encoding="utf-8")), 1):
            if "deployment" in block:
                programs[f"docs/{path.name}#{n}"] = block
    programs.update(ISSUE)
    return programs


def figures(text: str, target: str, split: bool) -> tuple[int, int, int, int] | None:
    """(fragments, largest, over the budget, total bytes); None if the program has errors."""
    result = check_text(text)
    if result.has_errors and any(d.code != "E601" for d in result.diagnostics if d.severity.name == "ERROR"):
        return None  # E601 (over a program slot) is what splitting may cure: counted
    saved = compiler.spare_numbers
    if not split:
        compiler.spare_numbers = lambda *_: None  # type: ignore[assignment]
    try:
        program = compiler.compile_model(result.model, target=target)
    finally:
        compiler.spare_numbers = saved
    if any(d.code != "E601" for d in program.diagnostics if d.severity.name == "ERROR"):
        return None
    over = sum(1 for f in program.fragments if f.size > program.program_budget)
    return len(program.fragments), program.max_fragment_bytes, over, program.total_bytes


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", choices=("default", "original"), default="default")
    parser.add_argument("--all", action="store_true", help="print every program")
    args = parser.parse_args()
    print(f"{'program':<40} {'fragments':>9} {'largest':>7} {'over':>4} {'bytes':>5}   "
          f"{'fragments':>9} {'largest':>7} {'over':>4} {'bytes':>5}")
    print(f"{'':<40} {'before':^30}   {'after':^30}")
    counted = over_before = over_after = changed = 0
    for name, text in corpus().items():
        before = figures(text, args.target, False)
        after = figures(text, args.target, True)
        if before is None or after is None:
            continue
        counted += 1
        over_before += before[2]
        over_after += after[2]
        changed += before != after
        if args.all or before != after or after[2]:
            print(f"{name:<40} {before[0]:>9} {before[1]:>7} {before[2]:>4} {before[3]:>5}   "
                  f"{after[0]:>9} {after[1]:>7} {after[2]:>4} {after[3]:>5}")
    print(f"{counted} programs compiled; {changed} changed; fragments over the budget: "
          f"{over_before} before, {over_after} after")
    return 0


if __name__ == "__main__":
    sys.exit(main())
