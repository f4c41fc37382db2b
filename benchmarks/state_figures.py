"""Figures of the state examples (issue 17): bytes and fragments against the 43-byte budget, the
time for the gradient and the count to settle on snake30 and 60-module random structures (in
hops x link latency, hops = the structure's depth from the entry module), transmissions per module
(program, value and role packets, acknowledgements and retries), and the largest state a module
holds.

Run: ``python benchmarks/state_figures.py [--seeds N]`` (lattice world, link latency 10 ms,
0 and 10 % packet loss). The settle time is the last change of any module's state or role after
the program was injected at t = 0.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.state.state_harness import compiled, hop_distances, run  # noqa: E402

EXAMPLES = ("gradient.rdcd", "count.rdcd", "lowest.rdcd")
STRUCTURES = ("snake30", "random60-seed14", "random60-seed19")
LATENCY_S = 0.01
BUDGET = 43


def sizes() -> list[str]:
    lines = ["bytes and fragments (default target, budget 43 program bytes):"]
    for name in EXAMPLES:
        program = compiled(name)
        fits = "fits" if program.max_fragment_bytes <= BUDGET else "OVER"
        lines.append(f"  {name:<16} {program.total_bytes:3d} bytes in {len(program.fragments)} fragment(s), "
                     f"largest {program.max_fragment_bytes} ({fits})")
    return lines


def settle_time(result) -> float:  # noqa: ANN001
    """The last state change on any module (exact, from the runtimes' histories)."""
    last = [t for r in result.world.runtimes.values() for t, _, _ in r.state_history]
    last += [t for r in result.world.runtimes.values() for t, _ in r.role_history]
    return max(last, default=0.0)


def state_bytes(result) -> int:  # noqa: ANN001
    """The most bytes of state one module holds: its state memory as the program uses it, the
    neighbours' values it keeps and its child marks."""
    own = len(result.program.states)
    return max(own + sum(v is not None for row in r.neighbour_cache for v in row) + 1
               for r in result.world.runtimes.values())


def settling(seeds: int) -> list[str]:
    lines = ["settling (lattice world, link latency 10 ms):"]
    for name in ("gradient.rdcd", "count.rdcd", "lowest.rdcd"):
        for structure in STRUCTURES:
            for loss in (0.0, 0.1):
                times, packets, held = [], [], []
                for seed in range(seeds):
                    result = run(name, structure, seed=seed, loss=loss)
                    depth = max(hop_distances(result.structure).values())
                    times.append(settle_time(result) / (depth * LATENCY_S))
                    packets.append(result.packets_per_module())
                    held.append(state_bytes(result))
                lines.append(f"  {name:<15} {structure:<16} loss {loss:.0%}: settles in "
                             f"{statistics.median(times):5.1f} x (hops x latency) (max {max(times):5.1f}), "
                             f"{statistics.median(packets):5.1f} transmissions per module (acks and "
                             f"retries included), state held <= {max(held)} bytes")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5, choices=range(1, 101), metavar="N",
                        help="seeds per case, 1..100 (default 5)")
    args = parser.parse_args()
    print("\n".join(sizes()))
    print("\n".join(settling(args.seeds)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
