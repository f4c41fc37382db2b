"""Real-time factor of the headless physics world.

    python benchmarks/sim_speed.py [--profile] [--repeat N]

Cases: car7 running the obstacle program towards a wall (60 s simulated); car17-wide likewise;
a random 100-module structure (seed 1) lying on the ground while a MIGRATE_CONTINUE fragment
diffuses through it (10 s). Prints simulated seconds per wall-clock second (what a user waits)
and per CPU second (less dependent on other load on the machine), the best of ``--repeat`` runs.
Targets: car7 >= 20x (aim 50x), 100 modules >= 2x.
"""

from __future__ import annotations

import argparse
import cProfile
import platform
import pstats
import sys
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sim.quiet import import_pybullet  # noqa: E402

import_pybullet()

from rdcd_core.cli_compile import compile_text  # noqa: E402
from sim import params  # noqa: E402
from sim.config import load_config, random_structure  # noqa: E402
from sim.obstacles import parse_obstacle  # noqa: E402
from sim.run import inject_program, role_table  # noqa: E402
from sim.world import PhysicsWorld  # noqa: E402
from vm.isa.assembler import assemble  # noqa: E402
from vm.roles import RoleTable  # noqa: E402


def _program():  # noqa: ANN202
    _, program, _ = compile_text((ROOT / "examples" / "obstacle_avoidance.rdcd").read_text(encoding="utf-8"))
    return program


def car(name: str, seconds: float) -> tuple[str, float, float, int]:
    program = _program()
    world = PhysicsWorld(load_config(name), obstacles=parse_obstacle("wall:1.0"))
    try:
        runtimes = world.add_runtimes(role_table(program), seed=0)
        inject_program(program, runtimes[world.structure.entry].inject)
        wall, cpu = time.perf_counter(), time.process_time()
        world.advance(seconds)
        return (f"{name} obstacle program", seconds / (time.perf_counter() - wall),
                seconds / (time.process_time() - cpu), world.robot.link_count)
    finally:
        world.close()


def random100(seconds: float) -> tuple[str, float, float, int]:
    structure = random_structure(100, 1)
    world = PhysicsWorld(structure)
    try:
        runtimes = world.add_runtimes(RoleTable(), seed=0)
        runtimes[structure.entry].inject(assemble("MIGRATE_CONTINUE"))
        wall, cpu = time.perf_counter(), time.process_time()
        world.advance(seconds)
        return ("random 100 modules, diffusion", seconds / (time.perf_counter() - wall),
                seconds / (time.process_time() - cpu), world.robot.link_count)
    finally:
        world.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", action="store_true", help="profile the car7 case and print the top 15")
    parser.add_argument("--repeat", type=int, default=1, metavar="N",
                        help="run each case N times and print the best (other load only slows a run down)")
    args = parser.parse_args()
    if args.profile:
        cProfile.runctx("car('car7', 60.0)", globals(), {}, "/tmp/sim_speed.prof")
        pstats.Stats("/tmp/sim_speed.prof").sort_stats("tottime").print_stats(15)
        return 0
    print(f"machine: {platform.processor() or platform.machine()}, Python {platform.python_version()}; "
          f"physics {params.PHYSICS_HZ:g} Hz, VM {params.VM_HZ:g} Hz, IR {params.IR_RATE_HZ:g} Hz, "
          f"{params.SOLVER_ITERATIONS} solver iterations")
    print(f"{'case':<32} {'links':>5} {'x real time (wall)':>19} {'x real time (CPU)':>18}")
    cases: list[Callable[[], tuple[str, float, float, int]]] = [
        lambda: car("car7", 60.0), lambda: car("car17-wide", 30.0), lambda: random100(10.0)]
    for case in cases:
        runs = [case() for _ in range(max(1, args.repeat))]
        name, _, _, links = runs[0]
        wall, cpu = max(r[1] for r in runs), max(r[2] for r in runs)
        print(f"{name:<32} {links:>5} {wall:>19.1f} {cpu:>18.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
