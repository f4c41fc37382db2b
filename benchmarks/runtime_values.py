"""Bytes of every fragment of issue 25's programs (values known only at run time, * / %) and of
every example, for the default and the original target.

Run: ``python benchmarks/runtime_values.py [--json OUT] [--before BEFORE.json]``.
``--json`` writes the figures; ``--before`` prints them beside figures written by an older checkout
(``PYTHONPATH=/path/to/old/checkout python benchmarks/runtime_values.py --json before.json``), so
that a change states, for each program, what it did to each fragment. A program that does not
compile shows the first error's code.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.append(str(ROOT))  # after PYTHONPATH: an older checkout given there is measured

from rdcd_core.compiler import compile_model  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402

_WHEELS = """state told := 0;
abstract role Wheel {
  abstract constant connected_direction, side;
  self.center_position == EAST_WEST;
  sizeof(self.total_connected()) == 1;
  sizeof(self.connected(connected_direction)) == 1;
  command go(speed) {
    BODY
  }
}
role RightWheel extends Wheel { constant connected_direction := EAST; constant side := 1; }
role LeftWheel extends Wheel { constant connected_direction := WEST; constant side := -1; }
role Axle {
  sizeof(connected_role(DOWN, Wheel)) > 0;
  startup begin() { self.sleep(); self.sleep(); Wheel.go(2); }
}
deployment { RightWheel, LeftWheel, Axle }
"""

# The programs, and the calls it names with a command's argument.
PROGRAMS: dict[str, str] = {
    "issue: go(speed) on a wheel": _WHEELS.replace(
        "BODY", "told := told + 1;\n    if (side > 0) self.turnContinuously(speed); "
                "else self.turnContinuously(-speed);"),
    "issue: go(speed) as speed * side": _WHEELS.replace(
        "BODY", "told := told + 1;\n    self.turnContinuously(speed * side);"),
    "go(speed) without the state": _WHEELS.replace("state told := 0;\n", "").replace(
        "BODY", "if (side > 0) self.turnContinuously(speed); else self.turnContinuously(-speed);"),
    "issue: behavior turnContinuously(a)": "state a := 3;\n"
                                           "role R { behavior b() { self.turnContinuously(a); } }\n"
                                           "deployment { R }\n",
    "turnTowards(v) in a command": "role R { command c(v) { self.turnTowards(v); } }\ndeployment { R }\n",
    "turnDegrees(v) in a command": "role R { command c(v) { self.turnDegrees(v); } }\ndeployment { R }\n",
    "sleepWhileTurning(v) in a command": "role R { command c(v) { self.sleepWhileTurning(v); } }\n"
                                         "deployment { R }\n",
    "a phase modulo 4 (gait)": "state phase := 0;\nrole R { behavior b() {\n  phase := (phase + 1) % 4;\n"
                               "  self.turnTowards(phase * 30 - 40); self.sleep(); } }\ndeployment { R }\n",
}


def measure(text: str, target: str) -> dict[str, object]:
    result = check_text(text, target=target)
    errors = [d for d in result.diagnostics if d.severity == 1]
    if errors:  # every code: a mistake that also gave a consequence shows both
        return {"error": " ".join(sorted({d.code for d in errors}))}
    program = compile_model(result.model, text=text, target=target)
    failed = [d for d in program.diagnostics if d.severity == 1]
    if failed:
        return {"error": " ".join(sorted({d.code for d in failed}))}
    return {"fragments": {f.name: [f.size, hashlib.sha256(bytes(f.code)).hexdigest()[:12]]
                          for f in program.fragments},
            "total": program.total_bytes,
            "W601": sorted({d.message.split()[1] for d in program.diagnostics if d.code == "W601"})}


def figures() -> dict[str, dict[str, object]]:
    texts = dict(PROGRAMS)
    for path in sorted((ROOT / "examples").glob("*.rdcd")):
        texts[f"examples/{path.name}"] = path.read_text(encoding="utf-8")
    return {f"{name} [{target}]": measure(text, target)
            for name, text in texts.items() for target in ("default", "original")}


def _fragments(entry: dict[str, object] | None) -> dict[str, list]:
    return dict(entry.get("fragments", {})) if entry else {}  # type: ignore[arg-type]


def show(now: dict[str, dict[str, object]], before: dict[str, dict[str, object]] | None) -> None:
    for name, entry in now.items():
        old = before.get(name) if before is not None else None
        if "error" in entry or (old is not None and "error" in old):
            was = f"{old.get('error') or old.get('total')}" if old is not None else ""
            now = entry.get("error") or entry.get("total")
            print(f"{name}: {now}" + (f"  (before: {was})" if was else ""))
            if "error" in entry:
                continue
        else:
            total = f"{old['total']} -> {entry['total']}" if old is not None else f"{entry['total']}"
            print(f"{name}: total {total} bytes" + (f"  W601 {entry['W601']}" if entry["W601"] else ""))
        previous = _fragments(old)
        for fragment, (size, digest) in _fragments(entry).items():
            if fragment in previous:
                was, was_digest = previous[fragment]
                change = "same bytes" if was_digest == digest else f"{was} -> {size}"
            else:
                change = "new" if old is not None else ""
            print(f"    {fragment:<34} {size:3d}  {change}")
        for fragment in previous.keys() - _fragments(entry).keys():
            print(f"    {fragment:<34}   -  (was {previous[fragment][0]})")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write the figures to this file")
    parser.add_argument("--before", type=Path, help="figures of an older checkout, shown beside")
    args = parser.parse_args()
    now = figures()
    if args.json:
        args.json.write_text(json.dumps(now, indent=1, sort_keys=True), encoding="utf-8")
    before = json.loads(args.before.read_text(encoding="utf-8")) if args.before else None
    show(now, before)
    return 0


if __name__ == "__main__":
    sys.exit(main())
