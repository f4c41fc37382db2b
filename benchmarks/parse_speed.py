"""Parser speed on a generated program of about 10,000 lines (the roles of the examples, repeated).

    python benchmarks/parse_speed.py [--lines 10000] [--repeat 7]

Prints the cold start (import + grammar tables), then the best and median parse time, wall clock
and CPU, of a clean file and of the same file with an error every 50 lines.
"""

from __future__ import annotations

import argparse
import re
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

ROLE_NAMES = ("RightWheel", "LeftWheel", "Reverse", "Axle", "Wheel")


def generate(lines: int) -> str:
    source = (ROOT / "examples" / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    roles = source[:source.index("deployment")]
    parts: list[str] = []
    deployed: list[str] = []
    count = 0
    copy = 0
    while count < lines:
        text = roles
        for name in ROLE_NAMES:
            text = re.sub(rf"\b{name}\b", f"{name}{copy}", text)
        parts.append(text)
        count += text.count("\n")
        deployed += [f"RightWheel{copy}", f"LeftWheel{copy}", f"Axle{copy}"]
        copy += 1
    return "".join(parts) + "deployment { " + ", ".join(deployed) + " }\n"


def damage(text: str, every: int = 50) -> str:
    lines = text.split("\n")
    for index in range(0, len(lines), every):
        lines[index] = lines[index].replace(";", "", 1)
    return "\n".join(lines)


def measure(parse, text: str, repeat: int) -> tuple[list[float], list[float], int]:  # noqa: ANN001
    walls, cpus = [], []
    diagnostics = 0
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        result = parse(text)
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
        diagnostics = len(result.diagnostics)
    return walls, cpus, diagnostics


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=10000)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args(argv)
    started = time.perf_counter()
    from rdcd_core.syntax import parse
    from rdcd_core.syntax.tables import tables

    tables()
    print(f"cold start (import + tables): {time.perf_counter() - started:.3f} s")
    clean = generate(args.lines)
    for label, text in (("clean", clean), ("damaged", damage(clean))):
        walls, cpus, diagnostics = measure(parse, text, args.repeat)
        print(f"{label:8s} {text.count(chr(10))} lines, {len(text)} chars, {diagnostics} diagnostics: "
              f"wall best {min(walls):.3f} s median {statistics.median(walls):.3f} s, "
              f"cpu best {min(cpus):.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
