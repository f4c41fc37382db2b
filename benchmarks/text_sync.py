"""Cost of one keystroke in the server's text synchronisation, on a generated program.

    python benchmarks/text_sync.py [--lines 10000] [--repeat 21]

For each line-break style (LF, CRLF, lone CR) prints the median time to build the line index of
the text (``rdcd_core.source.LineIndex``) and to apply one one-character edit near the end
(``server.sync.apply_change``, with and without a line index already built), and, for comparison,
pygls's own workspace document applying the same edit (the copy the server no longer keeps).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from lsprotocol import types  # noqa: E402
from pygls.workspace import TextDocument  # noqa: E402

from benchmarks.parse_speed import generate  # noqa: E402
from rdcd_core.source import LineIndex, normalize_newlines  # noqa: E402
from server.convert import Positions  # noqa: E402
from server.sync import apply_change  # noqa: E402


def median_ms(run: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=21)
    args = parser.parse_args()
    base = generate(args.lines)
    print(f"{args.lines} lines requested, {len(base):,} characters; median of {args.repeat}")
    for name, newline in (("LF", "\n"), ("CRLF", "\r\n"), ("CR", "\r")):
        text = normalize_newlines(base, newline)
        index = LineIndex(text)
        line = index.line_count - 3
        at = types.Position(line=line, character=2)
        change = types.TextDocumentContentChangePartial(range=types.Range(start=at, end=at), text="x")
        positions = Positions(index)

        def pygls_edit(text: str = text, change: types.TextDocumentContentChangePartial = change) -> str:
            document = TextDocument("file:///bench.rdcd", text,
                                    sync_kind=types.TextDocumentSyncKind.Incremental)
            document.apply_change(change)
            return document.source

        print(f"{name:>4}: {index.line_count:,} lines;"
              f" line index {median_ms(lambda t=text: LineIndex(t), args.repeat):.1f} ms,"
              f" edit {median_ms(lambda t=text, c=change: apply_change(t, c), args.repeat):.1f} ms,"
              f" edit with the index built {median_ms(lambda t=text, c=change, p=positions: apply_change(t, c, positions=p), args.repeat):.2f} ms,"  # noqa: E501
              f" pygls's edit {median_ms(pygls_edit, args.repeat):.1f} ms")


if __name__ == "__main__":
    main()
