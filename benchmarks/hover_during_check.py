"""Hover answered while a 10,000-line document is being checked, over a real LSP connection
(target: within 100 ms). The server checks in a worker thread; before, no request was answered
until the check ended.

A 10,000-line document (benchmarks/check_speed.py's program) is opened and checked, then edited;
while the server re-checks it, hovers are sent every 20 ms, on that document (answered from its
previous analysis, away from the edit) and on a small one. Prints the hover latencies until the
new diagnostics arrive, and how long the check took.

Run: ``python benchmarks/hover_during_check.py [--lines 10000]``.
"""

from __future__ import annotations

import argparse
import asyncio
import platform
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.check_speed import generate  # noqa: E402

BIG, SMALL = "file:///benchmark/big.rdcd", "file:///benchmark/small.rdcd"


def position_of(text: str, offset: int) -> types.Position:
    line = text.count("\n", 0, offset)
    return types.Position(line=line, character=offset - (text.rfind("\n", 0, offset) + 1))


async def run(lines: int) -> tuple[list[float], list[float], float]:
    client = LanguageClient("rdcd-benchmark", "1")
    published: dict[tuple[str, int], float] = {}

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: types.PublishDiagnosticsParams) -> None:
        if params.version is not None:
            published.setdefault((params.uri, params.version), time.perf_counter())

    await client.start_io(sys.executable, "-m", "server", "--debounce-ms", "10", "--log-level", "ERROR",
                          cwd=str(ROOT))
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    small = (ROOT / "examples" / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    big = generate(lines)
    for uri, text in ((SMALL, small), (BIG, big)):
        client.text_document_did_open(types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="rdcd", version=1, text=text)))
        await wait_for(published, (uri, 1))

    # an edit near the end of the big document: its re-check is the long one
    offset = big.rindex("self.setLed(") + len("self.setLed(")
    change = types.TextDocumentContentChangePartial(
        range=types.Range(start=position_of(big, offset), end=position_of(big, offset + 1)), text="5")
    edited = time.perf_counter()
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=BIG, version=2), content_changes=[change]))
    targets = {BIG: position_of(big, big.index("turn_direction") + 2),
               SMALL: position_of(small, small.index("turn_direction") + 2)}
    latencies: dict[str, list[float]] = {BIG: [], SMALL: []}
    while (BIG, 2) not in published:
        for uri, position in targets.items():
            started = time.perf_counter()
            answer = await client.text_document_hover_async(types.HoverParams(
                text_document=types.TextDocumentIdentifier(uri=uri), position=position))
            if (BIG, 2) not in published:  # answered while the check was still running
                latencies[uri].append((time.perf_counter() - started) * 1000)
            assert answer is not None, f"no hover on {uri}"
        await asyncio.sleep(0.02)
    checked = published[(BIG, 2)] - edited
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return latencies[BIG], latencies[SMALL], checked


async def wait_for(published: dict, key: tuple[str, int], timeout: float = 120) -> float:
    deadline = time.perf_counter() + timeout
    while key not in published:
        if time.perf_counter() > deadline:
            raise TimeoutError(f"no diagnostics for {key}")
        await asyncio.sleep(0.001)
    return published[key]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lines", type=int, default=10_000)
    args = parser.parse_args()
    on_big, on_small, checked = asyncio.run(run(args.lines))
    print(f"rdcd-lsp, hover during the re-check of a {args.lines}-line document "
          f"(the check took {checked:.2f} s); Python {platform.python_version()}")
    for label, values in (("hover, same document", on_big), ("hover, other document", on_small)):
        if values:
            print(f"  {label:22s} {len(values):3d} answered during the check: p50 "
                  f"{statistics.median(values):6.1f} ms   max {max(values):6.1f} ms")
        else:
            print(f"  {label:22s} none sent during the check (it was too quick)")


if __name__ == "__main__":
    main()
