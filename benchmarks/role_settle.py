"""Time for roles to settle after an outside change (issue 23), lattice world, in link latencies.

    python benchmarks/role_settle.py [--seeds N] [--at T]

Two programs whose roles depend on the shape: ``degree`` (below: a module's role is its number of
connections, so a detach changes the roles of its neighbours, and nothing waits) and
examples/lose_a_wheel.rdcd (a wheel on one connection, an axle above a wheel; the axle's discovery
starts with the compiler's ``SLEEP``, 1 s, to let the wheels take their roles first). For each
structure and seed, the seed picks a module other
than the entry module that can be detached, the run (that seed) detaches it at T s, when the roles
of the start have settled, and runs on for 10 s. Settling time: the last role change after the
change, minus T (0 when no role changed). Correct: the modules of the entry module's part end in
the roles a fresh start gives the shape that is left (a fresh run of the same program on it).
Latency: the lattice world's default link latency, 10 ms, no jitter.
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sim.quiet import import_pybullet  # noqa: E402

import_pybullet()

from rdcd_core.cli_compile import compile_text  # noqa: E402
from sim.config import load_config  # noqa: E402
from sim.run import Options, Run, simulate  # noqa: E402
from vm.lattice.outside import parse_all  # noqa: E402

CONFIGS = ("car7", "car11", "random60-seed1")
DEGREE = """
role Leaf { sizeof(self.total_connected()) == 1; }
role Link { sizeof(self.total_connected()) == 2; }
role Hub { sizeof(self.total_connected()) > 2; }
deployment { Leaf, Link, Hub }
"""
LATENCY_S = 0.01


def detachable(config: str, seed: int) -> int:
    structure = load_config(config)
    choices = sorted(m for m in structure.modules if m != structure.entry)
    rng = random.Random(seed)
    while True:
        mid = rng.choice(choices)
        if structure.copy().remove(mid).ok:
            return mid


def fresh_roles(program, config: str, without: int) -> dict[int, str | None]:  # noqa: ANN001
    structure = load_config(config)
    structure.remove(without)
    run = Run(program, structure, Options(world="lattice", obstacle="none", duration=10))
    run.run_to_end()
    part = structure.part_of(structure.entry)
    return {m: run.roles.name(rt.role) if rt.role else None for m, rt in run.runtimes.items() if m in part}


def one(program, config: str, seed: int, at: float) -> dict:  # noqa: ANN001
    mid = detachable(config, seed)
    options = Options(world="lattice", config=config, obstacle="none", duration=at + 10, seed=seed,
                      outside_changes=parse_all([f"{at:g}s:detach {mid}"]))
    report = simulate(program, load_config(config), options)
    before = [t for m in report["modules"] for t, _ in m["role_history"] if t <= at]
    after = [t for m in report["modules"] if m["final_lattice"] is not None
             for t, _ in m["role_history"] if t > at]
    changed = sum(1 for m in report["modules"] if m["final_lattice"] is not None
                  and any(t > at for t, _ in m["role_history"]))
    fresh = fresh_roles(program, config, mid)
    final = {m["id"]: m["final_role"] for m in report["modules"] if m["id"] in fresh}
    return {"module": mid, "settle_s": (max(after) - at) if after else 0.0, "changed": changed,
            "correct": final == fresh, "start_settled_s": max(before, default=0.0),
            "parts": len(report["parts"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--at", type=float, default=10.0)
    args = parser.parse_args()
    programs = {"degree": compile_text(DEGREE)[1], "lose_a_wheel": compile_text(
        (ROOT / "examples" / "lose_a_wheel.rdcd").read_text(encoding="utf-8"))[1]}
    print("| program | structure | runs | runs with a role change | settle, median (latencies) "
          "| settle, max (latencies) | roles right | wall s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for (name, program), config in ((p, c) for p in programs.items() for c in CONFIGS):
        t0 = time.perf_counter()
        results = [one(program, config, seed, args.at) for seed in range(1, args.seeds + 1)]
        wall = time.perf_counter() - t0
        assert all(r["start_settled_s"] < args.at for r in results)
        moved = [r["settle_s"] / LATENCY_S for r in results if r["changed"]]
        median = f"{statistics.median(moved):.0f}" if moved else "–"
        top = f"{max(moved):.0f}" if moved else "–"
        right = sum(r["correct"] for r in results)
        print(f"| {name} | {config} | {len(results)} | {len(moved)} | {median} | {top} "
              f"| {right}/{len(results)} | {wall:.1f} |")
        for r in results:
            print(f"    {name} {config}: detach {r['module']}: {r['changed']} changed, "
                  f"settle {r['settle_s'] / LATENCY_S:.0f} latencies, {r['parts']} parts, "
                  f"{'right' if r['correct'] else 'WRONG'}", file=sys.stderr)


if __name__ == "__main__":
    main()
