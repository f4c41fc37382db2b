"""How fast ``rdcd dap`` answers, measured through a real adapter process and a DAP client.

    python benchmarks/dap_speed.py [--repeat N] [--quick]

Cases (p95 of N round trips unless said):
- breakpoint hit → ``stopped``: ``continue`` to a breakpoint on the Axle's steering line, which
  runs every VM tick, so each round trip is one hit (an upper bound of hit → event);
- ``threads``, ``stackTrace``, ``scopes``, ``variables`` (every scope of the frame) while stopped on
  a 100-module snake (lattice world, snake_wave);
- a step (``next``) on car7;
- a 60-s car7 physics run with the debugger attached and no breakpoints against
  ``sim.run.simulate`` in process (best of 3 each);
- step back on a 60-s car7 physics run stopped at 55 s: ``stepBack`` → ``stopped``, and the
  adapter's resident memory before and after the run (checkpoints included).
Targets (issue 18): ≤ 50 ms, ≤ 20 ms, ≤ 100 ms, ≤ 5 % slower, ≤ 0.5 s.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "debug"))

from dap_client import Client  # noqa: E402

OBSTACLE = ROOT / "examples" / "obstacle_avoidance.rdcd"
SNAKE = ROOT / "examples" / "snake_wave.rdcd"
STEER_LINE = 42


def p95(samples: list[float]) -> float:
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, round(0.95 * (len(ordered) - 1)))]


def ms(samples: list[float]) -> str:
    median = statistics.median(samples)
    return f"p95 {1000 * p95(samples):.1f} ms (median {1000 * median:.1f} ms, n={len(samples)})"


def timed(client: Client, command: str, arguments: dict) -> tuple[float, dict]:
    start = time.perf_counter()
    response = client.request(command, arguments)
    return time.perf_counter() - start, response


def resume_and_wait(client: Client, command: str, arguments: dict) -> tuple[float, dict]:
    start = time.perf_counter()
    client.request(command, arguments)
    stop = client.stopped()
    return time.perf_counter() - start, stop


def rss_mb(client: Client) -> float:
    assert client.process is not None
    for line in Path(f"/proc/{client.process.pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def breakpoint_hits(n: int) -> None:
    client = Client.start(validate=False)
    try:
        client.launch(OBSTACLE, breakpoints=[{"line": STEER_LINE}], world="lattice", duration=3000,
                      obstacle="none")
        stop = client.stopped()
        samples = []
        for _ in range(n):
            dt, stop = resume_and_wait(client, "continue", {"threadId": stop["body"]["threadId"]})
            samples.append(dt)
        print(f"breakpoint hit → stopped (continue round trip): {ms(samples)}")
        thread = stop["body"]["threadId"]
        steps = []
        for _ in range(n):
            dt, stop = resume_and_wait(client, "next", {"threadId": thread})
            steps.append(dt)
        print(f"a step (next, car7 lattice): {ms(steps)}")
    finally:
        client.close()


def inspection(n: int) -> None:
    client = Client.start(validate=False)
    try:
        client.launch(SNAKE, breakpoints=[{"line": 9}], world="lattice", config="snake100", duration=60,
                      obstacle="none")
        stop = client.stopped()
        thread = stop["body"]["threadId"]
        times: dict[str, list[float]] = {"threads": [], "stackTrace": [], "scopes": [], "variables": []}
        for _ in range(n):
            dt, threads = timed(client, "threads", {})
            times["threads"].append(dt)
            dt, trace = timed(client, "stackTrace", {"threadId": thread})
            times["stackTrace"].append(dt)
            dt, scopes = timed(client, "scopes", {"frameId": trace["body"]["stackFrames"][0]["id"]})
            times["scopes"].append(dt)
            for scope in scopes["body"]["scopes"]:
                if scope["variablesReference"]:
                    dt, _ = timed(client, "variables", {"variablesReference": scope["variablesReference"]})
                    times["variables"].append(dt)
        print(f"100-module snake, {len(threads['body']['threads'])} threads:")
        for name, samples in times.items():
            print(f"  {name}: {ms(samples)}")
    finally:
        client.close()


def attached_run(repeat: int) -> None:
    from debug.code import CodeIndex
    from debug.engine import Engine, Sink
    from debug.inspect import names
    from debug.launch import prepare
    from sim.run import simulate

    launch = prepare({"program": str(OBSTACLE), "world": "physics", "duration": 60})

    class Done(Sink):
        def ended(self, run: object) -> None:
            self.end = time.perf_counter()

    plain, attached, plain_cpu, attached_cpu = [], [], [], []
    for _ in range(repeat):
        start, cpu = time.perf_counter(), time.process_time()
        simulate(launch.program, launch.structure, launch.options)
        plain.append(time.perf_counter() - start)
        plain_cpu.append(time.process_time() - cpu)
        sink = Done()
        code = CodeIndex(launch.program)
        engine = Engine(launch.program, launch.structure, launch.options, code, sink, names)
        start, cpu = time.perf_counter(), time.process_time()
        engine.start(stop_on_entry=False)
        engine._thread.join()  # type: ignore[union-attr]  # noqa: SLF001
        attached.append(sink.end - start)
        attached_cpu.append(time.process_time() - cpu)
        checkpoints = len(engine._checkpoints)  # noqa: SLF001
        engine.terminate()
    a, b = min(plain), min(attached)
    c, d = min(plain_cpu), min(attached_cpu)
    print(f"60-s car7 physics run: simulate {a:.2f} s, debugger attached (no breakpoints) {b:.2f} s: "
          f"{100 * (b / a - 1):+.1f} % wall; CPU {c:.2f} s vs {d:.2f} s: {100 * (d / c - 1):+.1f} % "
          f"(best of {repeat}; {checkpoints} checkpoints)")


def step_back(n: int) -> None:
    client = Client.start(validate=False)
    try:
        before = None
        client.request("initialize", {"adapterID": "rdcd"})
        before = rss_mb(client)
        late = [{"line": STEER_LINE, "condition": "time >= 55"}]
        client.launch(OBSTACLE, breakpoints=late, world="physics", duration=60)
        stop = client.stopped()
        client.request("setBreakpoints", {"source": {"path": str(OBSTACLE)}, "breakpoints": []})
        after = rss_mb(client)
        thread = stop["body"]["threadId"]
        samples = []
        for i in range(n):
            command = "stepBack" if i % 2 == 0 else "next"
            dt, stop = resume_and_wait(client, command, {"threadId": thread})
            if command == "stepBack":
                samples.append(dt)
        print(f"step back on a 60-s car7 physics run at {stop['body']['description']}: {ms(samples)}")
        print(f"  adapter memory: {before:.0f} MB before the launch, {after:.0f} MB at 55 s "
              f"({after - before:.0f} MB for the world and its checkpoints)")
    finally:
        client.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=60, help="round trips per case (default: 60)")
    parser.add_argument("--quick", action="store_true", help="fewer round trips, one attached run")
    args = parser.parse_args()
    if not 1 <= args.repeat <= 10_000:
        parser.error("--repeat must be 1..10000")
    n = 10 if args.quick else args.repeat
    print(f"{time.strftime('%Y-%m-%d')} on {platform.processor() or platform.machine()}, "
          f"Python {platform.python_version()}")
    breakpoint_hits(n)
    inspection(n)
    step_back(max(4, n // 3))
    attached_run(1 if args.quick else 5)


if __name__ == "__main__":
    main()
