"""Lattice throughput before and after structures that change (issue 23), alternated in one run.

    python benchmarks/lattice_changes.py [--base DIR] [--repeat N]

``--base``: a checkout of the commit before (e.g. ``git archive <commit> | tar -x -C DIR``); each
case runs in a fresh process of each tree in turn, ``--repeat`` times, and the best simulated
seconds per CPU second of each is printed. Without ``--base`` only this tree is measured. Cases
change nothing in the structure (the figure that must not get worse), plus one that moves a
module (examples/move_one.rdcd) for scale.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = {
    "car7 obstacle 60 s": ("examples/obstacle_avoidance.rdcd", "car7", "wall:1.0", 60.0),
    "car17-wide obstacle 60 s": ("examples/obstacle_avoidance.rdcd", "car17-wide", "wall:1.0", 60.0),
    "snake30 snake_wave 30 s": ("examples/snake_wave.rdcd", "snake30", "none", 30.0),
    "random60 gradient 30 s": ("examples/gradient.rdcd", "random60-seed1", "none", 30.0),
}
CHANGING = {"random4 move_one 10 s": ("examples/move_one.rdcd", "random4-seed109", "none", 10.0)}

_CHILD = """
import json, sys, time
sys.path.insert(0, {root!r})
from sim.quiet import import_pybullet
import_pybullet()
from rdcd_core.cli_compile import compile_text
from sim.config import load_config
from sim.run import Options, simulate
path, config, obstacle, duration = {case!r}
text = open({root!r} + "/" + path).read() if not path.startswith("/") else open(path).read()
program = compile_text(text)[1]
structure = load_config(config)
t0, c0 = time.perf_counter(), time.process_time()
simulate(program, structure, Options(world="lattice", config=config, obstacle=obstacle, duration=duration))
print(json.dumps({{"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0}}))
"""


def measure(root: Path, case: tuple, program_root: Path) -> dict:
    path = str(program_root / case[0])
    code = _CHILD.format(root=str(root), case=(path, *case[1:]))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, help="a checkout of the commit before")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    trees = [("after", ROOT)] + ([("before", args.base)] if args.base else [])
    for name, case in {**CASES, **CHANGING}.items():
        best: dict[str, float] = {}
        for i in range(args.repeat):
            for label, tree in trees if i % 2 == 0 else trees[::-1]:  # no tree always goes first
                if name in CHANGING and label == "before":
                    continue
                # the programs are this tree's (the examples are the same files in both)
                cpu = measure(tree, case, ROOT)["cpu"]
                best[label] = min(best.get(label, cpu), cpu)
        parts = [f"{label} {case[3] / best[label]:.0f}× ({best[label]:.3f} s CPU)" for label in best]
        change = ""
        if "before" in best:
            change = f", {100 * (best['after'] / best['before'] - 1):+.1f} % CPU"
        print(f"{name}: " + "; ".join(parts) + change, flush=True)


if __name__ == "__main__":
    main()
