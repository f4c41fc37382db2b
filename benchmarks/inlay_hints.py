"""Inlay hints (fragment sizes) for a whole document of 20,000 roles (target: under 1 s).

Run: ``python benchmarks/inlay_hints.py [--roles 20000]``. The document is checked first (as the
server does before it answers); the figure is the hints request itself, by
``rdcd_core.ide.inlay.fragment_hints`` over the whole text.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "compiler"))

from large_programs import many_roles, many_subroles  # noqa: E402

from rdcd_core.ide.analysis import analyze  # noqa: E402
from rdcd_core.ide.inlay import fragment_hints  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--roles", type=int, default=20_000)
    args = parser.parse_args()
    programs = (("roles", many_roles(args.roles)), ("subroles of one role", many_subroles(args.roles)))
    for label, text in programs:
        start = time.perf_counter()
        analysis = analyze(text)
        checked = time.perf_counter() - start
        start = time.perf_counter()
        hints = fragment_hints(analysis)
        took = time.perf_counter() - start
        print(f"{args.roles} {label}: check {checked:5.2f} s, inlay hints {took * 1000:7.1f} ms "
              f"({len(hints)} hints)", flush=True)


if __name__ == "__main__":
    main()
