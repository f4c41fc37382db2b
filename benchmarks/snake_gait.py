"""Net displacement in 60 s of examples/snake_gait.rdcd against examples/snake_wave.rdcd on the
same snakes, in the physics world (issue 17). Prints one line per snake:

    snake7  snake_wave 0.08 m  snake_gait 3.20 m  (40x)

Usage: python benchmarks/snake_gait.py [snake5 snake7 ...] [--duration S]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from rdcd_core.compiler import compile_model  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402
from sim.config import load_config  # noqa: E402
from sim.run import Options, simulate  # noqa: E402


def displacement(example: str, config: str, duration: float) -> float:
    """Net distance (m) between the robot's centre at the start and at the end of the run."""
    text = (ROOT / "examples" / example).read_text(encoding="utf-8")
    program = compile_model(check_text(text).model, text=text)
    report = simulate(program, load_config(config),
                      Options(world="physics", config=config, obstacle="none", duration=duration))
    (_, x0, y0, _), (_, x1, y1, _) = report["trajectory"][0], report["trajectory"][-1]
    return math.hypot(x1 - x0, y1 - y0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("snakes", nargs="*", default=["snake5", "snake7", "snake10"])
    parser.add_argument("--duration", type=float, default=60.0)
    args = parser.parse_args()
    for config in args.snakes:
        wave = displacement("snake_wave.rdcd", config, args.duration)
        gait = displacement("snake_gait.rdcd", config, args.duration)
        print(f"{config:8} snake_wave {wave:.2f} m  snake_gait {gait:.2f} m  ({gait / wave:.0f}x)",
              flush=True)


if __name__ == "__main__":
    main()
