"""The replay (``rdcd simulate --replay``): file size, recording cost, playback speed.

    python benchmarks/replay_size_speed.py [--repeat N] [--screenshot docs/replay.png]

1. size of the replay of a 60-s car7 run (physics, obstacle program, wall at 1 m); target <= 1.5 MB;
2. recording cost: simulate() with and without a recording, best of N runs each (wall and CPU
   seconds) for car7 physics 60 s, car7 lattice 60 s, car17-wide lattice 60 s; target <= 15 %;
3. playback in headless Chromium with software WebGL (SwiftShader), 1280x720: median time of a
   frame (pose update + render + wait for the GPU) over 120 frames spread across the run, the
   camera following the robot, for car17-wide (physics, 30 s) and a random 100-module structure
   (seed 1, physics, 10 s, as in sim_speed.py); target <= 33 ms (aim 16 ms).
Needs node, Chromium and ``npm ci`` in sim/replay/viewer for 3. (skipped with the reason if not).
"""

from __future__ import annotations

import argparse
import platform
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sim.quiet import import_pybullet  # noqa: E402

import_pybullet()

from rdcd_core.cli_compile import compile_text  # noqa: E402
from sim.config import load_config, random_structure  # noqa: E402
from sim.replay.page import write_page  # noqa: E402
from sim.replay.recording import Recording  # noqa: E402
from sim.replay.sources import SourceIndex  # noqa: E402
from sim.run import Options, simulate  # noqa: E402
from tests.replay.browser import missing, probe  # noqa: E402

SOURCE = (ROOT / "examples" / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
PROGRAM = compile_text(SOURCE)[1]


def structure(config: str):  # noqa: ANN201
    return random_structure(100, 1) if config == "random100" else load_config(config)


def run(config: str, world: str, seconds: float, record: bool) -> tuple[float, float, Recording | None, dict]:
    s = structure(config)
    recording = Recording(s, SourceIndex(PROGRAM, SOURCE), seconds) if record else None
    options = Options(world=world, config=config, obstacle="wall:1.0", duration=seconds, recording=recording)
    wall, cpu = time.perf_counter(), time.process_time()
    report = simulate(PROGRAM, s, options)
    return time.perf_counter() - wall, time.process_time() - cpu, recording, report


def page(config: str, world: str, seconds: float, folder: Path) -> tuple[Path, int]:
    _, _, recording, report = run(config, world, seconds, True)
    path = folder / f"{config}-{world}.html"
    size = write_page(str(path), recording, PROGRAM, structure(config), report, "obstacle_avoidance.rdcd")
    return path, size


def overhead(config: str, world: str, seconds: float, repeat: int) -> None:
    plain, recorded = [], []
    for _ in range(repeat):  # interleaved, so that load on the machine hits both alike
        plain.append(run(config, world, seconds, False)[:2])
        recorded.append(run(config, world, seconds, True)[:2])
    (pw, pc), (rw, rc) = (min(r[0] for r in plain), min(r[1] for r in plain)), \
        (min(r[0] for r in recorded), min(r[1] for r in recorded))
    print(f"  {config} {world} {seconds:g} s: without {pw:6.2f} s wall {pc:6.2f} s CPU; "
          f"with {rw:6.2f} s wall {rc:6.2f} s CPU; "
          f"cost {100 * (rw / pw - 1):+5.1f} % wall, {100 * (rc / pc - 1):+5.1f} % CPU")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, metavar="N",
                        help="runs per overhead case (the best is kept)")
    parser.add_argument("--screenshot", metavar="PNG", help="also save a screenshot of the car7 replay here")
    args = parser.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, Python {platform.python_version()}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        car7, size = page("car7", "physics", 60.0, folder)
        print(f"1. replay of car7, 60 s, physics: {size / 1e6:.3f} MB (target <= 1.5 MB)")
        print(f"2. recording cost (best of {args.repeat}):")
        overhead("car7", "physics", 60.0, args.repeat)
        overhead("car7", "lattice", 60.0, args.repeat)
        overhead("car17-wide", "lattice", 60.0, args.repeat)
        reason = missing()
        if reason:
            print(f"3. playback: skipped ({reason})")
            return 0
        print("3. playback, headless Chromium, SwiftShader, 1280x720, 120 frames:")
        for config, seconds in (("car17-wide", 30.0), ("random100", 10.0)):
            path, size = page(config, "physics", seconds, folder)
            result = probe(path, width=1280, height=720, frames=120, timeout=900)
            assert result["ready"] == "true" and not result["pageErrors"], result
            times = sorted(result["frames"]["times"][1:])  # the first frame compiles the shaders
            p90 = times[int(len(times) * 0.9)]
            print(f"  {config} ({size / 1e6:.2f} MB): median {result['frames']['median']:.1f} ms, "
                  f"90th percentile {p90:.1f} ms (target <= 33 ms, aim 16 ms)")
        if args.screenshot:
            data_events = __import__("tests.replay.helpers", fromlist=["page_data"]).page_data(
                car7.read_text(encoding="utf-8"))["events"]
            handler = next(i for i, e in enumerate(data_events) if e[2] == "handler")
            probe(car7, width=1280, height=900, module=4, moduleTime=16.0, event=handler,
                  shot=str(Path(args.screenshot).resolve()), shotTime=16.5, follow=True)
            print(f"screenshot: {args.screenshot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
