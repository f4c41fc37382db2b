"""Why a car turns as it does: wheel loads, wheel speeds and axle angles over a physics run.

    python benchmarks/wheel_loads.py [--config car17-wide] [--obstacle wall:1.0] [--duration 60]
                                     [--every 2]

Every ``--every`` simulated seconds it prints the heading, each wheel's ground load (N) with an
``R`` while the wheel plays ``Reverse``, each wheel's joint speed as a fraction of the nominal
one turn in 6 s, and each axle's joint angle. At the end it lists how long each wheel spent in
each ``Reverse`` span: the program reverses every wheel for three turns of its own joint, so a
wheel slowed by its load stays in ``Reverse`` longer than the others.

This is the measurement behind README's note on car17-wide.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sim.quiet import import_pybullet  # noqa: E402

import_pybullet()

import pybullet as pb  # noqa: E402

from rdcd_core.cli_compile import compile_text  # noqa: E402
from sim import params  # noqa: E402
from sim.config import load_config  # noqa: E402
from sim.obstacles import parse_obstacle  # noqa: E402
from sim.run import inject_program, role_table  # noqa: E402
from sim.world import PhysicsWorld  # noqa: E402
from vm.lattice.structure import Structure  # noqa: E402

PROGRAM = ROOT / "examples" / "obstacle_avoidance.rdcd"


def _wheel_links(world: PhysicsWorld) -> dict[int, int]:
    """Link index of each ground wheel's ringed hemisphere -> module id (ringed modules that sit
    higher up, like a bridge module with a free hemisphere, never touch the ground)."""
    ringed = {mid: mb for mid, mb in world.robot.modules.items() if mb.wheel_side}
    lowest = min((world.structure.modules[mid].position[2] for mid in ringed), default=0)
    return {mb.links[mb.wheel_side]: mid for mid, mb in ringed.items()
            if world.structure.modules[mid].position[2] == lowest}


def _axles(structure: Structure, wheels: set[int]) -> list[int]:
    """The modules the wheels hang on."""
    return sorted({n for w in wheels for n, _ in structure.neighbours(w).values()})


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default="car17-wide")
    parser.add_argument("--obstacle", default="wall:1.0")
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--every", type=float, default=2.0)
    args = parser.parse_args(argv)

    _, program, _ = compile_text(PROGRAM.read_text(encoding="utf-8"))
    assert program is not None
    structure = load_config(args.config)
    world = PhysicsWorld(structure, obstacles=parse_obstacle(args.obstacle))
    wheel_of_link = _wheel_links(world)
    wheels = sorted(wheel_of_link.values())
    axles = _axles(structure, set(wheels))
    reverse_since: dict[int, float] = {}
    spans: list[tuple[int, float, float]] = []

    def on_event(mid: int):  # noqa: ANN202
        def record(kind: str, detail: dict) -> None:
            if kind != "role":
                return
            if detail["name"].startswith("Reverse"):
                reverse_since.setdefault(mid, world.time)
            elif mid in reverse_since:
                spans.append((mid, reverse_since.pop(mid), world.time))
        return record

    runtimes = world.add_runtimes(role_table(program), seed=0)
    for mid, runtime in runtimes.items():
        runtime.on_event = on_event(mid)
    inject_program(program, runtimes[structure.entry].inject)
    print(f"{args.config}, obstacle {args.obstacle}: load N (R = Reverse) | joint speed / nominal | "
          f"axle angle deg")
    print("     t  heading | " + " ".join(f"{w:>6}" for w in wheels) + " | "
          + " ".join(f"{w:>5}" for w in wheels) + " | " + " ".join(f"{a:>4}" for a in axles))
    try:
        elapsed = 0.0
        while elapsed < args.duration - 1e-9:
            turns = {w: world.joints[w].turns for w in wheels}
            step = min(args.every, args.duration - elapsed)
            world.advance(step)
            elapsed += step
            load = dict.fromkeys(wheels, 0.0)
            for contact in pb.getContactPoints(bodyA=world.robot.body, bodyB=world.ground,
                                               physicsClientId=world.client):
                if contact[3] in wheel_of_link:
                    load[wheel_of_link[contact[3]]] += contact[9]
            period = params.JOINT_TURN_PERIOD_S
            speed = {w: (world.joints[w].turns - turns[w]) * period / step for w in wheels}
            heading = world.tracking.trajectory[-1][3]
            print(f"{elapsed:6.1f} {heading:8.1f} | "
                  + " ".join(f"{load[w]:5.1f}{'R' if w in reverse_since else ' '}" for w in wheels) + " | "
                  + " ".join(f"{speed[w]:5.2f}" for w in wheels) + " | "
                  + " ".join(f"{world.joints[a].angle_deg():4.0f}" for a in axles))
    finally:
        world.close()
    spans += [(mid, start, world.time) for mid, start in reverse_since.items()]
    print("Reverse spans (nominal 3 turns = "
          f"{3 * params.JOINT_TURN_PERIOD_S:.0f} s): wheel start-end (length)")
    for mid, start, end in sorted(spans, key=lambda s: (s[1], s[0])):
        still = " (still reversing)" if mid in reverse_since and end == world.time else ""
        print(f"  {mid:>3}  {start:6.2f}-{end:6.2f}  ({end - start:5.2f} s){still}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
