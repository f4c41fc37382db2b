"""Inputs that used to fall off a cliff (issue 10): how long `check_text` takes on one role with
20,000 invariants and on a method with 15,000 `if`s (targets: under 2 s each), and whether the
time grows linearly (half the size should take about half the time).

Run: ``python benchmarks/cliffs.py [--scale 1.0]``. Prints wall and CPU seconds per input.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "compiler"))

from large_programs import many_ifs, many_invariants  # noqa: E402

from rdcd_core.frontend import check_text  # noqa: E402

CASES = {
    "role with {n} invariants": (many_invariants, 20_000, {}),
    "behavior with {n} if/else": (many_ifs, 15_000, {"kind": "behavior"}),
    "command with {n} ifs": (many_ifs, 15_000, {"kind": "command", "with_else": False}),
    "startup with {n} ifs": (many_ifs, 15_000, {"kind": "startup", "with_else": False}),
}


def measure(text: str) -> tuple[float, float, int]:
    wall, cpu = time.perf_counter(), time.process_time()
    result = check_text(text)
    return time.perf_counter() - wall, time.process_time() - cpu, len(result.diagnostics)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--scale", type=float, default=1.0, help="multiply every size by this")
    args = parser.parse_args()
    print(f"python {platform.python_version()} on {platform.machine()}, {platform.system()}")
    check_text(many_ifs(50))  # imports and the parser's tables, outside the figures
    for label, (generate, size, options) in CASES.items():
        n = max(1, int(size * args.scale))
        wall, cpu, found = measure(generate(n, **options))
        half_wall, _, _ = measure(generate(n // 2, **options))
        print(f"{label.format(n=n):32s} {wall:6.2f} s wall {cpu:6.2f} s cpu  "
              f"(half the size: {half_wall:5.2f} s; ratio {wall / max(half_wall, 1e-6):3.1f}, "
              f"linear is 2)  {found} diagnostics", flush=True)


if __name__ == "__main__":
    main()
