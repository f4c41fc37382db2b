"""Acceptance scenarios of the obstacle program in the physics world; prints a table.

    python benchmarks/scenarios.py [--quick] [--loss-runs 20] [--jobs 1]

Rows: car7, car11, car8-cyclic, car17-wide with a wall 1 m ahead (60 s); car7 with no obstacle
(20 s, must drive straight); then ``--loss-runs`` runs of car7 wall:1.0 at 10 % packet loss with
seeds 1..N. Exit status 0 when every row passes.
"""

from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

PROGRAM = ROOT / "examples" / "obstacle_avoidance.rdcd"


def compile_program():  # noqa: ANN201
    from rdcd_core.cli_compile import compile_text

    _, program, _ = compile_text(PROGRAM.read_text(encoding="utf-8"))
    return program


def run_case(case: tuple[str, str, float, int, float]) -> dict:
    from sim.quiet import import_pybullet

    import_pybullet()
    from sim.config import load_config
    from sim.run import Options, simulate
    from sim.scenario import (
        forward_at_end,
        heading_deviation,
        judge_obstacle,
        judge_straight,
        no_reverse_left,
        reverse_spans,
        turn_deg,
    )

    config, obstacle, duration, seed, loss = case
    structure = load_config(config)
    options = Options(config=config, obstacle=obstacle, duration=duration, seed=seed, packet_loss=loss)
    report = simulate(compile_program(), structure, options)
    checks = (judge_straight if obstacle == "none" else judge_obstacle)(report, structure)
    first = next((e["t"] for e in report["events"] if e["kind"] == "handler"), None)
    end = "reversing" if not no_reverse_left(report) else "forward" if forward_at_end(report) else "other"
    turn = turn_deg(report) if obstacle != "none" else heading_deviation(report["trajectory"])
    spans = " ".join(f"{a:.0f}-{'end' if b is None else f'{b:.0f}'}" for a, b in reverse_spans(report))
    return {"case": case, "checks": checks, "turn": turn, "end": end, "spans": spans or "-",
            "detect_t": first, "min_d": report["min_obstacle_distance_m"], "rtf": report["real_time_factor"],
            "dropped": report["messages"]["dropped"]}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loss-runs", type=int, default=20)
    parser.add_argument("--loss", type=float, default=0.1)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--quick", action="store_true", help="only car7 wall and car7 none")
    args = parser.parse_args()
    cases = [(c, "wall:1.0", 60.0, 0, 0.0) for c in ("car7", "car11", "car8-cyclic", "car17-wide")]
    cases.append(("car7", "none", 20.0, 0, 0.0))
    cases += [("car7", "wall:1.0", 60.0, seed, args.loss) for seed in range(1, args.loss_runs + 1)]
    if args.quick:
        cases = [cases[0], cases[4]]
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(run_case, cases))
    print(f"{'config':<12} {'obstacle':<9} {'seed':>4} {'loss':>5} {'detect s':>8} {'min d m':>8} "
          f"{'reversing s':<13} {'turn °':>7} {'at end':>9} {'rtf':>6}  result")
    failures = 0
    for r in results:
        config, obstacle, _, seed, loss = r["case"]
        bad = [k for k, ok in r["checks"].items() if not ok]
        failures += bool(bad)
        detect = f"{r['detect_t']:.1f}" if r["detect_t"] is not None else "-"
        min_d = f"{r['min_d']:.3f}" if r["min_d"] is not None else "-"
        turn = f"{r['turn']:+.1f}" if r["turn"] is not None else "-"
        print(f"{config:<12} {obstacle:<9} {seed:>4} {loss:>5.2f} {detect:>8} {min_d:>8} {r['spans']:<13} "
              f"{turn:>7} {r['end']:>9} {r['rtf']:>6.1f}  {'PASS' if not bad else 'FAIL: ' + ', '.join(bad)}")
    print(f"{len(results) - failures}/{len(results)} passed in {time.perf_counter() - start:.0f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
