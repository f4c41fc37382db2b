"""Latency of rdcd-lsp seen by a real LSP client over stdio, on a generated 2,000-line document.

Measures, as p50/p95 over many samples:
- edit → diagnostics: from sending ``didChange`` to receiving ``publishDiagnostics`` for that
  version, minus the server's debounce delay;
- completion after ``self.`` and hover on names, on the checked document.

Run: ``python benchmarks/lsp_latency.py [--lines 2000] [--samples 60] [--debounce-ms 50]``.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import platform
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

ROOT = Path(__file__).resolve().parent.parent
URI = "file:///benchmark/big.rdcd"


HEADER = """// generated for benchmarks: many wheel-like roles
abstract role Wheel {
  abstract constant connected_direction, event_handler, turn_direction;
  self.center_position == EAST_WEST;
  sizeof(self.total_connected()) == 1;
  sizeof(self.connected(connected_direction)) == 1;
  startup move() {
    if (self.y() > 0)
      self.handleEvent(event_handler, { self.disableEvent(event_handler); Wheel.stop(); });
    self.turnContinuously(turn_direction);
  }
  command stop() {
    self.assumeRole(Reverse, {
      self.turnContinuously(-turn_direction);
      self.sleepWhileTurning(3);
      self.turnContinuously(turn_direction);
      self.enableEvent(event_handler);
    });
  }
}

role Reverse modifies Wheel { }
"""

ROLE = """
abstract role Part{n} extends Wheel {{
  constant connected_direction := EAST;
  constant turn_direction := {speed};
  constant event_handler := EVENT_PROXIMITY_{event};
  self.x() == {n};
  plain{n}() {{
    self.setLed({led});
    if (self.y() > {led} && self.z() < 3)
      self.turnTowards(30);
    else
      self.turnTowards(-30);
  }}
  behavior wobble{n}() {{
    self.plain{n}();
    self.sleep();
  }}
}}
"""

FOOTER = """
role Axle {
  sizeof(connected_role(DOWN, Wheel)) > 0;
  behavior steer() {
    if (connected_role(DOWN, Reverse) > 0)
      self.turnTowards(30);
    else
      self.turnTowards(0);
  }
}

deployment { Axle }
"""


def big_program(lines: int = 2000) -> str:
    parts = [HEADER]
    count = 0
    while sum(p.count("\n") for p in parts) + FOOTER.count("\n") < lines:
        parts.append(ROLE.format(n=count, speed=1 + count % 5, event=count % 8, led=count % 7))
        count += 1
    parts.append(FOOTER)
    return "".join(parts)


def percentile(values: list[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(fraction * (len(ordered) - 1))))]


def position_of(text: str, offset: int) -> types.Position:
    line = text.count("\n", 0, offset)
    return types.Position(line=line, character=offset - (text.rfind("\n", 0, offset) + 1))


async def run(lines: int, samples: int, debounce_ms: float) -> dict[str, list[float]]:
    client = LanguageClient("rdcd-benchmark", "1")
    published: dict[int, float] = {}

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diagnostics(params: types.PublishDiagnosticsParams) -> None:
        if params.version is not None:
            published.setdefault(params.version, time.perf_counter())

    await client.start_io(sys.executable, "-m", "server", "--debounce-ms", str(debounce_ms),
                          "--log-level", "ERROR",
                          *os.environ.get("RDCD_LSP_ARGS", "").split(), cwd=str(ROOT))
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    text = big_program(lines)
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        text_document=types.TextDocumentItem(uri=URI, language_id="rdcd", version=1, text=text)))
    await wait_for(published, 1)

    results: dict[str, list[float]] = {"edit→diagnostics": [], "completion": [], "hover": []}
    target = text.index("self.setLed(") + len("self.setLed(")
    version = 1
    for sample in range(samples):
        # an edit in the middle of the file: change the digit of one setLed argument
        offset = text.index("self.setLed(", target + sample * 7 % 5000) + len("self.setLed(")
        digit = str(sample % 7)
        change = types.TextDocumentContentChangePartial(
            range=types.Range(start=position_of(text, offset), end=position_of(text, offset + 1)), text=digit)
        text = text[:offset] + digit + text[offset + 1:]
        version += 1
        sent = time.perf_counter()
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=version),
            content_changes=[change]))
        received = await wait_for(published, version)
        results["edit→diagnostics"].append((received - sent) * 1000 - debounce_ms)

        at = text.index("self.", offset) + len("self.")
        started = time.perf_counter()
        await client.text_document_completion_async(types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri=URI), position=position_of(text, at)))
        results["completion"].append((time.perf_counter() - started) * 1000)

        name = text.index("turn_direction", offset) + 3
        started = time.perf_counter()
        await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=URI), position=position_of(text, name)))
        results["hover"].append((time.perf_counter() - started) * 1000)

    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return results


async def wait_for(published: dict[int, float], version: int, timeout: float = 30) -> float:
    deadline = time.perf_counter() + timeout
    while version not in published:
        if time.perf_counter() > deadline:
            raise TimeoutError(f"no diagnostics for version {version}")
        await asyncio.sleep(0.0005)
    return published[version]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lines", type=int, default=2000)
    parser.add_argument("--samples", type=int, default=60)
    parser.add_argument("--debounce-ms", type=float, default=50)
    args = parser.parse_args()
    results = asyncio.run(run(args.lines, args.samples, args.debounce_ms))
    print(f"rdcd-lsp latency, {args.lines}-line document, {args.samples} samples, "
          f"debounce {args.debounce_ms:g} ms excluded; {platform.processor() or platform.machine()}, "
          f"Python {platform.python_version()}")
    for name, values in results.items():
        print(f"  {name:18s} p50 {statistics.median(values):6.1f} ms   p95 {percentile(values, 0.95):6.1f} ms"
              f"   max {max(values):6.1f} ms")


if __name__ == "__main__":
    main()
