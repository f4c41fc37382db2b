"""Throughput of rdcd-lsp's stdio reader (``server/framing.py``), seen by a raw client.

Prints the time for: many small requests written at once and answered; one 50 MB frame (a
notification the server ignores) followed by a request; 10 MB of noise followed by a request (the
server resynchronises on the next header).

Run: ``python benchmarks/lsp_framing.py [--requests 5000] [--megabytes 50]``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.server.rawclient import RawServer, frame, request  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=5000)
    parser.add_argument("--megabytes", type=int, default=50)
    args = parser.parse_args()
    server = RawServer(log_level="ERROR")
    try:
        server.initialize()
        print(f"rdcd-lsp stdio reader; {platform.machine()}, Python {platform.python_version()}, "
              f"{os.cpu_count()} cores")
        started = time.perf_counter()
        server.send(b"".join(request(i, "workspace/symbol", {"query": "nothing-here"})
                             for i in range(args.requests)))
        for i in range(args.requests):
            server.answer(i, timeout=300)
        elapsed = time.perf_counter() - started
        print(f"  {args.requests} small requests written at once: {elapsed:6.2f} s "
              f"({elapsed / args.requests * 1e6:.0f} µs each, answers included)")

        body = json.dumps({"jsonrpc": "2.0", "method": "rdcd/unknown",
                           "params": {"text": "x" * (args.megabytes * 1_000_000)}}).encode()
        started = time.perf_counter()
        server.send(frame(body) + request("after-big", "workspace/symbol", {"query": "nothing-here"}))
        server.answer("after-big", timeout=300)
        print(f"  one {args.megabytes} MB frame, then a request:     {time.perf_counter() - started:6.2f} s")

        noise = random.Random(0).randbytes(10_000_000)
        started = time.perf_counter()
        server.send(noise + request("after-noise", "workspace/symbol", {"query": "nothing-here"}))
        server.answer("after-noise", timeout=300)
        print(f"  10 MB of noise, then a request:        {time.perf_counter() - started:6.2f} s")
        server.stop()
    finally:
        server.kill()
    return 0


if __name__ == "__main__":
    sys.exit(main())
