"""Reconfiguration sequences (docs/reconfiguration.md): success rate and time to reconfigure in the
lattice world under packet loss, forward and backwards; bytes and fragments; rdcd check speed.

Run: ``python benchmarks/reconfiguration.py [--seeds N] [--reverse-seeds N] [--losses 0,0.1,0.2,0.3]
[--duration S] [FILE ...]`` (default: examples/eight_to_snake.rdcd from eight7, 50 seeds forward,
20 backwards; ``--reverse-seeds 0`` for examples/car_to_snake.rdcd, which cannot be run
backwards). A run succeeds when its final structure (cells and connections) is the shape the
checker finds at the end (backwards: the starting configuration).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rdcd_core.compiler import compile_model  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402
from sim.config import load_config  # noqa: E402
from sim.run import Options, simulate  # noqa: E402

STRUCTURE_EVENTS = ("connect", "disconnect", "rotation_end")


def shape_of_report(report: dict) -> tuple:
    cells = {m["id"]: tuple(m["final_lattice"]) for m in report["modules"]}
    return cells, {tuple(c) for c in report["connections"]}


def shape_of(structure) -> tuple:  # noqa: ANN001
    cells = {m: tuple(s.position) for m, s in structure.modules.items()}
    return cells, {(k.a, k.a_physical, k.b, k.b_physical) for k in structure.links()}


def runs(text: str, config: str, name: str, reverse: bool, seeds: int, loss: float,
         duration: float) -> tuple[int, list[float]]:
    result = check_text(text)
    trace = result.traces[0]
    start = trace.final if reverse else load_config(config)
    goal = shape_of(load_config(config) if reverse else trace.final)
    program = compile_model(result.model, text=text, reverse=name if reverse else None)
    ok, times = 0, []
    for seed in range(seeds):
        options = Options(world="lattice", config=config, obstacle="none", duration=duration, seed=seed,
                          packet_loss=loss)
        report = simulate(program, start.copy(), options)
        if shape_of_report(report) == goal:
            ok += 1
            times.append(max(e["t"] for e in report["events"] if e["kind"] in STRUCTURE_EVENTS))
    return ok, times


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", default=[str(ROOT / "examples" / "eight_to_snake.rdcd")])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--reverse-seeds", type=int, default=20)
    parser.add_argument("--losses", default="0,0.1,0.2,0.3")
    parser.add_argument("--duration", type=float, default=30.0)
    args = parser.parse_args()
    losses = [float(x) for x in args.losses.split(",")]
    for path in args.files:
        text = Path(path).read_text(encoding="utf-8")
        started = time.perf_counter()
        for _ in range(20):
            result = check_text(text)
        check_ms = (time.perf_counter() - started) / 20 * 1000
        program = compile_model(result.model, text=text)
        sequence = result.program.sequences[0]
        config = sequence.config.text if sequence.config is not None else "car7"
        steps = sum(1 for item in sequence.items for _ in getattr(item, "steps", (item,)))
        print(f"{Path(path).name}: {steps} steps from {config}; {len(program.fragments)} fragments, "
              f"{program.total_bytes} bytes, largest {max(f.size for f in program.fragments)}; "
              f"rdcd check {check_ms:.1f} ms (mean of 20)")
        for reverse, seeds in ((False, args.seeds), (True, args.reverse_seeds)):
            if seeds <= 0:  # e.g. a sequence that cannot be run backwards (car_to_snake)
                continue
            for loss in losses:
                ok, times = runs(text, config, sequence.name.text, reverse, seeds, loss, args.duration)
                spread = (f"time to reconfigure median {statistics.median(times):.2f} s, "
                          f"max {max(times):.2f} s" if times else "no success")
                print(f"  {'backwards' if reverse else 'forward'} loss {loss:.0%}: {ok}/{seeds} runs end "
                      f"in the target shape; {spread}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
