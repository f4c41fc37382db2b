"""Fuzzes the front end: random text, random token sequences and mutated examples.

Every case goes through ``rdcd_core.syntax.parse`` and ``rdcd_core.semantics.analyze``. Prints
the number of cases, the time, and every exception; exits 1 on any exception or on a diagnostic
whose span lies outside the text.

    python benchmarks/parse_fuzz.py [-n 10000] [--seed 1]
"""

from __future__ import annotations

import argparse
import random
import sys
import time
import traceback
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rdcd_core.semantics import analyze  # noqa: E402
from rdcd_core.syntax import parse  # noqa: E402
from rdcd_core.syntax.keywords import KEYWORDS  # noqa: E402
from tests.syntax.fuzz_inputs import PUNCT, edit, example_sources, tokens_of  # noqa: E402

WORDS = [*KEYWORDS, "x", "Wheel", "sizeof", "connected_role", "EAST", "turnTowards", "y", "_a1"]
NUMBERS = ["0", "1", "127", "128", "300", "99999999999999999999"]
ODD = ["/*", "*/", "//", "\n", "@", "=", "é", "\t", "\x00", "#", "\"", "'", ":", "&", "|"]


def random_text(rng: random.Random, _: list[str]) -> str:
    alphabet = "abcdefxyz_AZ019 \n\t{}();,.:=|&!<>+-/*@é#"
    return "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 200)))


def random_tokens(rng: random.Random, _: list[str]) -> str:
    vocabulary = PUNCT + WORDS + NUMBERS + ODD
    return " ".join(rng.choice(vocabulary) for _ in range(rng.randint(0, 120)))


def mutated_example(rng: random.Random, sources: list[str]) -> str:
    tokens = tokens_of(rng.choice(sources))
    for _ in range(rng.randint(1, 6)):
        if not tokens:
            break
        index = rng.randrange(len(tokens))
        operation = rng.choice(("delete", "duplicate", "swap", "insert", "replace"))
        word = ""
        if operation == "insert":
            word = rng.choice(PUNCT + WORDS + ODD)
        elif operation == "replace":
            word = rng.choice(PUNCT + WORDS + NUMBERS)
        edit(tokens, operation, index, word)
    return " ".join(tokens)


GENERATORS: list[Callable[[random.Random, list[str]], str]] = [random_text, random_tokens, mutated_example]


def check_case(text: str) -> str | None:
    """None if the case is fine, else a description of the failure."""
    try:
        result = parse(text)
    except Exception:  # noqa: BLE001
        return "parse raised:\n" + traceback.format_exc()
    for diagnostic in result.diagnostics:
        span = diagnostic.span
        if not 0 <= span.start <= span.end <= len(text):
            return f"diagnostic span {span} outside the text (length {len(text)}): {diagnostic}"
    try:
        analyze(result.program)
    except Exception:  # noqa: BLE001
        return "analyze raised:\n" + traceback.format_exc()
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=10000, help="number of cases (default 10000)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    sources = example_sources()
    failures = 0
    started = time.perf_counter()
    for case in range(args.n):
        text = GENERATORS[case % len(GENERATORS)](rng, sources)
        problem = check_case(text)
        if problem is not None:
            failures += 1
            if failures <= 20:
                print(f"--- case {case}: {text!r}\n{problem}")
    elapsed = time.perf_counter() - started
    print(f"{args.n} cases (parse + analyze) in {elapsed:.1f} s, {failures} failing")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
