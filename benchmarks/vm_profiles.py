"""The two VM profiles side by side (issue 11): what each example does on each car in the default
VM and in the original firmware's profile, compiled for either target; prints a table.

    python benchmarks/vm_profiles.py [--world lattice|physics] [--duration 90]

Columns: roles taken, obstacle detections, runtime errors (the first one), packets sent, wall
time and real-time factor. Figures are indicative on a loaded machine. In the original profile the
entry module first loads the fragments, 8 s each (the firmware's dcd_action), hence 90 s.

Then the comparison with the firmware: the profile run in each of the 60 contexts recorded from the
ATRON firmware's own code (tests/firmware/README.md), and how many agree module by module.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

CASES = [  # (program, config, compiled for, VM profile)
    ("obstacle_avoidance.rdcd", "car7", "default", "default"),
    ("obstacle_avoidance.rdcd", "car7", "original", "original"),
    ("obstacle_avoidance.rdcd", "car7", "default", "original"),
    ("obstacle_avoidance.rdcd", "car11", "original", "original"),
    ("obstacle_avoidance.rdcd", "car8-cyclic", "original", "default"),
    ("obstacle_avoidance.rdcd", "car8-cyclic", "original", "original"),
    ("snake_wave.rdcd", "snake5", "original", "original"),
    ("snake_wave.rdcd", "snake5", "default", "original"),
]


def run_case(name: str, config: str, target: str, vm: str, world: str, duration: float) -> list[str]:
    from collections import Counter

    from rdcd_core.cli_compile import compile_text
    from sim.config import load_config
    from sim.run import Options, simulate

    _, program, _ = compile_text((ROOT / "examples" / name).read_text(encoding="utf-8"), target=target)
    assert program is not None
    began = time.perf_counter()
    report = simulate(program, load_config(config),
                      Options(world=world, config=config, obstacle="wall:1.0", duration=duration, vm=vm))
    wall = time.perf_counter() - began
    roles = Counter(m["final_role"] for m in report["modules"] if m["final_role"])
    errors = [e for m in report["modules"] for e in m["errors"]]
    first = errors[0]["message"][:60] if errors else ""
    return [name.split("_")[0], config, target, vm, " ".join(f"{n}×{r}" for r, n in sorted(roles.items())),
            str(report["obstacle_detections"]), f"{len(errors)} {first}".strip(),
            str(report["messages"]["sent"]), f"{wall:.1f}", f"{duration / wall:.0f}×"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", choices=("lattice", "physics"), default="lattice")
    parser.add_argument("--duration", type=float, default=90.0)
    args = parser.parse_args()
    from sim.quiet import import_pybullet

    import_pybullet()
    head = ["program", "config", "target", "vm", "roles", "detect", "errors", "sent", "wall s", "rtf"]
    rows = [head] + [run_case(*case, args.world, args.duration) for case in CASES]
    widths = [max(len(row[i]) for row in rows) for i in range(len(head))]
    for row in rows:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)))
    firmware_agreement()
    return 0


def firmware_agreement() -> None:
    from tests.firmware.test_firmware_agreement import profile_run, recorded

    began = time.perf_counter()
    contexts = recorded()["contexts"]
    differing = [c for c in contexts if profile_run(c) != c["modules"]]
    print(f"\nfirmware's recorded figures: {len(contexts) - len(differing)} / {len(contexts)} contexts agree "
          f"module by module ({time.perf_counter() - began:.1f} s)")
    for c in differing:
        print(f"  differs: {c['program']} on {c['config']}, {c['scenario']}")


if __name__ == "__main__":
    sys.exit(main())
