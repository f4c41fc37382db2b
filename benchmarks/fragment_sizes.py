"""Per-fragment sizes and totals of the compiled example programs.

Run: ``python benchmarks/fragment_sizes.py [--max-packet N] [--target default|original] [FILE...]``
(default: examples/*.rdcd, the default target).
Reference for the obstacle program (docs/vm.md): hand-written bytecode 7 fragments, 200 bytes,
largest 53; the paper's compiler about twice the fragments, each about 50 % larger.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rdcd_core.compiler import compile_model  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402

HAND_WRITTEN = {"obstacle_avoidance.rdcd": (7, 200, 53)}


def report(path: Path, budget: int, target: str = "default") -> list[str]:
    text = path.read_text(encoding="utf-8")
    started = time.perf_counter()
    result = check_text(text, packet_budget=budget)
    if result.has_errors:
        return [f"{path.name}: has errors, not compiled"]
    program = compile_model(result.model, packet_budget=budget, text=text, target=target)
    elapsed = (time.perf_counter() - started) * 1000
    lines = [f"{path.name}  (target {program.target}, budget {program.program_budget} program bytes, "
             f"check + compile {elapsed:.0f} ms)"]
    for fragment in program.fragments:
        lines.append(f"  {fragment.name:<36} {fragment.kind:<10} {fragment.size:3d} bytes")
    lines.append(f"  total {program.total_bytes} bytes in {len(program.fragments)} fragments, "
                 f"largest {program.max_fragment_bytes}")
    if path.name in HAND_WRITTEN:
        count, total, largest = HAND_WRITTEN[path.name]
        lines.append(f"  hand-written: {total} bytes in {count} fragments, largest {largest}")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", type=Path)
    parser.add_argument("--max-packet", type=int, default=50)
    parser.add_argument("--target", choices=("default", "original"), default="default")
    args = parser.parse_args()
    files = args.files or sorted((ROOT / "examples").glob("*.rdcd"))
    for path in files:
        print("\n".join(report(path, args.max_packet, args.target)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
