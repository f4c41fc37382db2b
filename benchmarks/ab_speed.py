"""car7's physics real-time factor in two source trees, alternated in one run on one machine.

    git archive <commit> | tar -x -C /tmp/before
    python benchmarks/ab_speed.py --before /tmp/before [--rounds N] [--seconds S]

Each round runs ``benchmarks/sim_speed.py``'s car7 case (the obstacle program towards a wall) once
in the other tree, then once in this one, each in a fresh process that imports only its own tree;
alternating spreads the load of other jobs on the machine over both. Prints every run and the
best and median of each side, per wall-clock and per CPU second.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PROBE = """
import importlib.util, json, sys
spec = importlib.util.spec_from_file_location("sim_speed", sys.argv[1])
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
_, wall, cpu, links = module.car("car7", float(sys.argv[2]))
print(json.dumps([wall, cpu, links]))
"""


def run(tree: Path, seconds: float) -> tuple[float, float]:
    script = tree / "benchmarks" / "sim_speed.py"
    out = subprocess.run([sys.executable, "-c", PROBE, str(script), str(seconds)],
                         cwd=tree, capture_output=True, text=True, check=True)
    wall, cpu, _ = json.loads(out.stdout.strip().splitlines()[-1])
    return wall, cpu


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, type=Path, help="the other source tree")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=60.0, help="simulated seconds per run")
    args = parser.parse_args()
    sides: dict[str, list[tuple[float, float]]] = {"before": [], "after": []}
    for i in range(max(1, args.rounds)):
        for name, tree in (("before", args.before.resolve()), ("after", ROOT)):
            wall, cpu = run(tree, args.seconds)
            sides[name].append((wall, cpu))
            print(f"round {i + 1} {name:<6} x{wall:6.1f} wall  x{cpu:6.1f} CPU", flush=True)
    for name, runs in sides.items():
        walls, cpus = [r[0] for r in runs], [r[1] for r in runs]
        print(f"{name:<6} best x{max(walls):.1f} wall, x{max(cpus):.1f} CPU; "
              f"median x{statistics.median(walls):.1f} wall, x{statistics.median(cpus):.1f} CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
