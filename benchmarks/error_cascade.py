"""Diagnostics per injected mistake: one error per mistake (docs/benchmarks.md).

The corpus is the one the fuzz tests mutate (tests/syntax/fuzz_inputs.py: the examples), each
with one mistake at a time: a token replaced by a bad character (``#``, ``@``), a stray ``#``
inserted, a token deleted, duplicated or swapped with the next, at every ``--every``-th token. Only
mistakes that make a syntax error count. Before: the parser's diagnostics plus everything the
checker then says (what ``check_text`` reported until consequences were dropped); after:
``check_text``. Prints errors per mistake (mean, and how many mistakes give more than one) and all
diagnostics per mistake.

    python benchmarks/error_cascade.py [--every 3]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rdcd_core.diagnostics import Severity  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402
from rdcd_core.semantics import analyze  # noqa: E402
from rdcd_core.syntax import parse  # noqa: E402
from tests.syntax.fuzz_inputs import EXAMPLES, MUTATED_EXAMPLES, edit, spaced_tokens  # noqa: E402

MISTAKES = (("replace", "#"), ("replace", "@"), ("insert", "#"), ("delete", ""), ("duplicate", ""),
            ("swap", ""))


def mutants(text: str, every: int) -> list[str]:
    tokens = spaced_tokens(text)  # whitespace kept: comments stay on their lines
    words = [i for i, t in enumerate(tokens) if not t.isspace()]
    found = []
    for index in words[::every]:
        for operation, word in MISTAKES:
            changed = list(tokens)
            edit(changed, operation, index, word)
            found.append("".join(changed))
    return found


def counts(text: str, base: tuple[int, int] = (0, 0)) -> tuple[tuple[int, int], tuple[int, int]] | None:
    """((errors, diagnostics) before, (errors, diagnostics) after) beyond the unchanged program's
    ``base``; None without a syntax error."""
    parsed = parse(text)
    if sum(1 for d in parsed.diagnostics if d.severity is Severity.ERROR) <= base[0]:
        return None
    before = list(parsed.diagnostics) + list(analyze(parsed.program).diagnostics)
    after = check_text(text).diagnostics
    return ((_errors(before) - base[0], len(before) - base[1]),
            (_errors(after) - base[0], len(after) - base[1]))


def _errors(found: list) -> int:
    return sum(1 for d in found if d.severity is Severity.ERROR)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=3, help="mutate every N-th token (default 3)")
    args = parser.parse_args()
    print(f"{'program':<26} {'mistakes':>8}  {'errors/mistake before':>22} {'after':>6}  "
          f"{'>1 error before':>15} {'after':>6}  {'diagnostics before':>18} {'after':>6}")
    totals = [0, 0, 0, 0, 0, 0, 0]
    for name in MUTATED_EXAMPLES:
        text = (EXAMPLES / name).read_text(encoding="utf-8")
        unchanged = check_text(text).diagnostics  # figure5_verbatim has its stray brace
        base = (_errors(unchanged), len(unchanged))
        rows = [c for c in (counts(m, base) for m in mutants(text, args.every)) if c is not None]
        n = len(rows)
        eb = sum(b[0] for b, _ in rows)
        ea = sum(a[0] for _, a in rows)
        mb = sum(1 for b, _ in rows if b[0] > 1)
        ma = sum(1 for _, a in rows if a[0] > 1)
        db = sum(b[1] for b, _ in rows)
        da = sum(a[1] for _, a in rows)
        for i, v in enumerate((n, eb, ea, mb, ma, db, da)):
            totals[i] += v
        print(_row(name, n, eb, ea, mb, ma, db, da))
    print(_row("all", *totals))
    return 0


def _row(name: str, n: int, eb: int, ea: int, mb: int, ma: int, db: int, da: int) -> str:
    n1 = max(n, 1)
    return (f"{name:<26} {n:>8}  {eb / n1:>22.2f} {ea / n1:>6.2f}  {mb:>15} {ma:>6}  "
            f"{db / n1:>18.2f} {da / n1:>6.2f}")


if __name__ == "__main__":
    sys.exit(main())
