"""Reconfiguration sequences (docs/reconfiguration.md): success rate and time to reconfigure under
packet loss, forward and backwards, in the lattice or the physics world; sequential against
parallel steps; rollback when one step fails; bytes and fragments; rdcd check speed.

Run: ``python benchmarks/reconfiguration.py [--world lattice|physics] [--seeds N]
[--reverse-seeds N] [--losses 0,0.1,0.2,0.3] [--duration S] [FILE ...]`` (default:
examples/eight_to_snake.rdcd from eight7, lattice, 50 seeds forward, 20 backwards;
``--reverse-seeds 0`` to run forward only). A run succeeds
when its final structure (cells and connections) is the shape the checker finds at the end
(backwards: the starting configuration); in the physics world each failure is given its cause.

``--parallel``: the time to reconfigure of the same steps one after the other and in parallel
blocks (eight_to_snake and tests/sequences/eight_to_snake_parallel.rdcd; the half turns of
tests/sequences/parallel_turns.rdcd; eight_to_car's steps alone, tests/sequences/
eight_to_car_parallel.rdcd; car_to_snake and tests/sequences/car_to_snake_parallel.rdcd), each
against the same file without its blocks (or the example); ``--case`` picks by title.

``--rollback``: one step fails at random in every run (a seeded choice among the latch and
unlatch steps: an unlatch meets ``jam`` — its latch no longer moves —, a latch ``fail`` — it does
not close, once; vm/lattice/outside.py); counts the runs that end in the start shape, the target
shape, or in between (eight_to_snake and car_to_snake with ``rollback``, tests/sequences/relatch.rdcd,
eight_to_car's steps alone with ``rollback``).

``--overlap FILE``: which neighbouring steps of an example could form a parallel block: both orders
run in the lattice model and end in the same structure, and they touch different modules (the
checker's rule for a block); with the time each step took in a lattice run without loss (from the
module's action to the progress it sets, first heard anywhere: waiting for code or progress is
left out, a block does not shorten it), what blocks of such steps would save at most: the
estimate that ``--parallel`` measures with the pairs that fit (tests/sequences/*_parallel.rdcd).

``--crawl``: car_to_snake in the physics world, forward and backwards: how far the robot's centre
moves (net, start to end) from the moment the first module hears that the sequence is done to the
end of the run: the chain's crawl forward, the car given back standing still backwards.
"""

from __future__ import annotations

import argparse
import math
import random
import statistics
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rdcd_core.compiler import compile_model  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402
from rdcd_core.sequences.check import constant_arg, steps_of  # noqa: E402
from rdcd_core.sequences.progress import done_value, is_rollback, rolled_back_value  # noqa: E402
from rdcd_core.sequences.roles import vm_frames  # noqa: E402
from sim.config import load_config  # noqa: E402
from sim.run import Options, simulate  # noqa: E402
from tests.sequences.programs import EIGHT_TO_CAR_STEPS, with_rollback, without_blocks  # noqa: E402
from vm.lattice.outside import parse_all  # noqa: E402

TOO_BIG = {"E121", "E805"}  # what a program with parallel blocks may meet, not the lattice model
STRUCTURE_EVENTS = ("connect", "disconnect", "rotation_end")
EIGHT = ROOT / "examples" / "eight_to_snake.rdcd"
CAR_TO_SNAKE = ROOT / "examples" / "car_to_snake.rdcd"
DATA = ROOT / "tests" / "sequences"


def shape_of_report(report: dict) -> tuple:
    cells = {m["id"]: tuple(m["final_lattice"]) if m["final_lattice"] else None for m in report["modules"]}
    return cells, {tuple(c) for c in report["connections"]}


def shape_of(structure) -> tuple:  # noqa: ANN001
    cells = {m: tuple(s.position) for m, s in structure.modules.items()}
    return cells, {(k.a, k.a_physical, k.b, k.b_physical) for k in structure.links()}


def done_time(report: dict) -> float:
    return max((e["t"] for e in report["events"] if e["kind"] in STRUCTURE_EVENTS), default=0.0)


def finals(text: str) -> set[int]:
    """The progress values a sequence ends with: done (and rolled back, with ``rollback``)."""
    sequence = check_text(text).program.sequences[0]
    n = sum(1 for _ in steps_of(sequence))
    return {done_value(sequence), rolled_back_value(n)} if is_rollback(sequence) else {done_value(sequence)}


def cause(report: dict, goal: tuple, name: str, final: set[int]) -> str:
    """Why a run did not end in the goal shape, in a few words: still running when the run ended
    (the progress is not one final value everywhere), or what failed."""
    failed = [e for e in report["events"] if e["kind"].endswith("_failed")]
    progress = sorted({m.get("final_state", {}).get(name) for m in report["modules"]} - {None})
    first = (f"; first failure: {failed[0]['kind']} of module {failed[0]['module']} "
             f"({failed[0]['detail'].get('cause', '?')})" if failed else "")
    if len(progress) != 1 or progress[0] not in final:
        return f"still running when the run ended, progress {progress}{first}"
    cells, links = shape_of_report(report)
    if links == goal[1]:
        return f"connections right, cells differ, progress {progress}{first}"
    return f"progress {progress} everywhere{first}"


def prepare(text: str, reverse: bool, name: str):  # noqa: ANN201 - (program, start, goal, frames)
    """Backwards: the robot as the forward run leaves it, each module in the frame it learned."""
    result = check_text(text)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    trace = result.traces[0]
    config = result.program.sequences[0].config.text
    start = trace.final if reverse else load_config(config)
    goal = shape_of(load_config(config) if reverse else trace.final)
    frames = vm_frames(trace.learned) if reverse else {}
    return compile_model(result.model, text=text, reverse=name if reverse else None), start, goal, frames


def runs(text: str, config: str, name: str, reverse: bool, seeds: int, loss: float,
         duration: float, world: str = "lattice") -> tuple[int, list[float], list[str]]:
    program, start, goal, frames = prepare(text, reverse, name)
    ok, times, causes = 0, [], []
    for seed in range(seeds):
        options = Options(world=world, config=config, obstacle="none", duration=duration, seed=seed,
                          packet_loss=loss, frames=frames)
        report = simulate(program, start.copy(), options)
        if shape_of_report(report) == goal:
            ok += 1
            times.append(done_time(report))
        else:
            causes.append(f"seed {seed}: {cause(report, goal, name, finals(text))}")
    return ok, times, causes


def spread(times: list[float]) -> str:
    if not times:
        return "no success"
    return f"median {statistics.median(times):.2f} s, max {max(times):.2f} s"


def main_default(args: argparse.Namespace) -> None:
    losses = [float(x) for x in args.losses.split(",")]
    for path in args.files:
        text = Path(path).read_text(encoding="utf-8")
        started = time.perf_counter()
        for _ in range(20):
            result = check_text(text)
        check_ms = (time.perf_counter() - started) / 20 * 1000
        program = compile_model(result.model, text=text)
        sequence = result.program.sequences[0]
        config = sequence.config.text if sequence.config is not None else "car7"
        steps = sum(1 for _ in steps_of(sequence))
        print(f"{Path(path).name}: {steps} steps from {config}; {len(program.fragments)} fragments, "
              f"{program.total_bytes} bytes, largest {max(f.size for f in program.fragments)}; "
              f"rdcd check {check_ms:.1f} ms (mean of 20); world {args.world}")
        for reverse, seeds in ((False, args.seeds), (True, args.reverse_seeds)):
            if seeds <= 0:  # forward only
                continue
            for loss in losses:
                began = time.perf_counter()
                ok, times, causes = runs(text, config, sequence.name.text, reverse, seeds, loss,
                                         args.duration, args.world)
                wall = time.perf_counter() - began
                print(f"  {'backwards' if reverse else 'forward'} loss {loss:.0%}: {ok}/{seeds} runs end "
                      f"in the target shape; time to reconfigure {spread(times)} ({wall:.0f} s wall)",
                      flush=True)
                for line in causes:
                    print(f"    {line}", flush=True)


def main_parallel(args: argparse.Namespace) -> None:
    turns = (DATA / "parallel_turns.rdcd").read_text()
    parallel_eight = (DATA / "eight_to_snake_parallel.rdcd").read_text()
    eight_to_car = (DATA / "eight_to_car_parallel.rdcd").read_text()
    # (title, configuration, one after the other, parallel, shortest duration: the examples take
    # 10-25 s without loss)
    pairs = [("eight_to_snake: two unlatches", "eight7", EIGHT.read_text(), parallel_eight, 0.0),
             ("parallel_turns: two unlatches, two half turns", "eight7", without_blocks(turns), turns, 0.0),
             ("eight_to_car: its 23 steps alone, four pairs as blocks", "eight7",
              without_blocks(eight_to_car), eight_to_car, 90.0),
             ("car_to_snake: the example, two pairs as blocks", "car7", CAR_TO_SNAKE.read_text(),
              (DATA / "car_to_snake_parallel.rdcd").read_text(), 90.0)]
    for loss in [float(x) for x in args.losses.split(",")]:
        for title, config, sequential, parallel, shortest in pairs:
            if args.case not in title:
                continue
            for kind, text in (("one after the other", sequential), ("parallel block", parallel)):
                name = check_text(text).program.sequences[0].name.text
                ok, times, causes = runs(text, config, name, False, args.seeds, loss,
                                         max(args.duration, shortest), args.world)
                print(f"{title}, {kind}, loss {loss:.0%}: {ok}/{args.seeds} in the target shape; time to "
                      f"reconfigure {spread(times)}; mean {statistics.mean(times):.2f} s" if times else
                      f"{title}, {kind}, loss {loss:.0%}: {ok}/{args.seeds}", flush=True)
                for line in causes:
                    print(f"    {line}", flush=True)


def faults_for(text: str) -> list[str]:
    """For each latch or unlatch step, the fault that makes it fail (at 0 s)."""
    result = check_text(text)
    trace = result.traces[0]
    out = []
    for step, done in zip(steps_of(result.program.sequences[0]), trace.results, strict=False):
        action = step.action.text
        if action in ("connect", "disconnect"):
            kind = "fail" if action == "connect" else "jam"
            out.append(f"0s:{kind} {done.module} {constant_arg(step, result.model)}")
    return out


def main_rollback(args: argparse.Namespace) -> None:
    eight = with_rollback(EIGHT.read_text())
    car = with_rollback(CAR_TO_SNAKE.read_text())
    # eight_to_car's 23 steps alone: with rollback a block runs one step after the other
    eight_to_car = with_rollback(without_blocks(EIGHT_TO_CAR_STEPS.read_text()))
    cases = [("eight_to_snake (rollback)", eight), ("relatch", (DATA / "relatch.rdcd").read_text()),
             ("car_to_snake (rollback, compact form)", car),
             ("eight_to_car's steps (rollback, compact form)", eight_to_car)]
    for loss in [float(x) for x in args.losses.split(",")]:
        for title, text in cases:
            if args.case not in title:
                continue
            config = check_text(text).program.sequences[0].config.text
            program, start, target, _ = prepare(text, False, "")
            begin = shape_of(start)
            name = check_text(text).program.sequences[0].name.text
            faults = faults_for(text)
            ends: Counter[str] = Counter()
            chosen: Counter[str] = Counter()
            between = []
            for seed in range(args.seeds):
                fault = random.Random(seed).choice(faults)
                chosen[fault] += 1
                options = Options(world=args.world, config=config, obstacle="none", duration=args.duration,
                                  seed=seed, packet_loss=loss, outside_changes=parse_all([fault]))
                report = simulate(program, start.copy(), options)
                final = shape_of_report(report)
                end = "start" if final == begin else "target" if final == target else "between"
                ends[end] += 1
                if end == "between":  # run it again four times as long: only later, or never?
                    longer = Options(world=args.world, config=config, obstacle="none",
                                     duration=4 * args.duration, seed=seed, packet_loss=loss,
                                     outside_changes=parse_all([fault]))
                    again = shape_of_report(simulate(program, start.copy(), longer))
                    later = "start" if again == begin else "target" if again == target else "between"
                    why = cause(report, target, name, finals(text))
                    between.append(f"seed {seed} ({fault}): {why}; run for {4 * args.duration:g} s it "
                                   f"ends in the {later} shape")
            print(f"{title}, loss {loss:.0%}, {args.seeds} runs, one step failing at random "
                  f"({', '.join(f'{f} x{n}' for f, n in sorted(chosen.items()))}): start shape "
                  f"{ends['start']}, target shape {ends['target']}, in between {ends['between']}", flush=True)
            for line in between:
                print(f"    {line}", flush=True)


def _reordered(text: str, lines: list[int], order: list[int]) -> str:
    out = text.split("\n")
    steps = [out[i] for i in lines]
    for i, k in zip(lines, order, strict=True):
        out[i] = steps[k]
    return "\n".join(out)


def main_overlap(args: argparse.Namespace) -> None:
    for path in args.files:
        text = Path(path).read_text(encoding="utf-8")
        result = check_text(text)
        sequence = result.program.sequences[0] if result.program.sequences else None
        if sequence is None or sequence.config is None or result.has_errors or result.traces[0].final is None:
            print(f"{Path(path).name}: needs a sequence with a configuration that checks clean", flush=True)
            continue
        name, config = sequence.name.text, sequence.config.text
        final = shape_of(result.traces[0].final)
        lines = [i for i, line in enumerate(text.split("\n"))
                 if any(line.strip().startswith(f"{s.role.text}(") for s in steps_of(sequence))]
        report = simulate(compile_model(result.model, text=text), load_config(config),
                          Options(world="lattice", config=config, obstacle="none", duration=args.duration))
        first = {0: 0.0}
        for m in report["modules"]:
            for t, state, value in m["state_history"]:
                if state == name and (value not in first or t < first[value]):
                    first[value] = t
        n = len(lines)
        if n not in first:
            print(f"{Path(path).name}: not done in {args.duration:g} s; give a longer --duration", flush=True)
            continue
        modules = [r.module for r in result.traces[0].results]
        acted = [max((e["t"] for e in report["events"] if e["kind"] == "action"
                      and e["module"] == modules[k] and e["t"] <= first[k + 1]), default=first[k])
                 for k in range(n)]
        spans = [first[k + 1] - acted[k] for k in range(n)]  # from the action to its progress
        free = []
        for a in range(n - 1):
            order = list(range(n))
            order[a], order[a + 1] = a + 1, a
            swapped = check_text(_reordered(text, lines, order))
            block = text.split("\n")
            block[lines[a]] = "  parallel { " + block[lines[a]].split("//")[0].strip()
            block[lines[a + 1]] = "  " + block[lines[a + 1]].split("//")[0].strip() + " }"
            as_block = check_text("\n".join(block))
            found = (*swapped.diagnostics, *as_block.diagnostics)
            model_says = [d.code for d in found if d.code not in TOO_BIG]  # E121, E805: not the model's
            if (not model_says and swapped.traces[0].final is not None
                    and shape_of(swapped.traces[0].final) == final):
                free.append(a)
        best = [0.0] * (n + 1)  # at most one block per neighbouring pair, pairs disjoint
        for k in range(2, n + 1):
            saved = min(spans[k - 2], spans[k - 1]) if k - 2 in free else 0.0
            best[k] = max(best[k - 1], best[k - 2] + saved)
        print(f"{Path(path).name}: {n} steps, {first[n]:.2f} s one after the other (lattice, no loss); "
              f"steps that could share a block: {', '.join(f'{a + 1}+{a + 2}' for a in free) or 'none'}; "
              f"pairs of them as blocks would save at most {best[n]:.2f} s", flush=True)
        times = ", ".join(f"{k + 1}: {s:.2f}" for k, s in enumerate(spans))
        print(f"    each step's action, seconds: {times}", flush=True)


def main_crawl(args: argparse.Namespace) -> None:
    text = CAR_TO_SNAKE.read_text()
    name = check_text(text).program.sequences[0].name.text
    done = next(iter(finals(text)))
    for reverse, seeds in ((False, args.seeds), (True, args.reverse_seeds)):
        program, start, goal, frames = prepare(text, reverse, name)
        for loss in [float(x) for x in args.losses.split(",")]:
            nets, spans, missed = [], [], []
            for seed in range(seeds):
                options = Options(world="physics", config="car7", obstacle="none", duration=args.duration,
                                  seed=seed, packet_loss=loss, frames=frames)
                report = simulate(program, start.copy(), options)
                heard = [t for m in report["modules"] for t, state, value in m["state_history"]
                         if state == name and value == done]
                if not heard or shape_of_report(report) != goal:
                    missed.append(f"seed {seed}: {cause(report, goal, name, {done})}")
                    continue
                path = [p for p in report["trajectory"] if p[0] >= min(heard)]
                nets.append(math.dist(path[0][1:3], path[-1][1:3]))
                spans.append(path[-1][0] - path[0][0])
            figures = (f"net {statistics.median(nets):.3f} m median (min {min(nets):.3f}, max "
                       f"{max(nets):.3f}) in {statistics.median(spans):.1f} s median" if nets else "no run")
            way = "backwards" if reverse else "forward"
            print(f"car_to_snake {way}, loss {loss:.0%}: {len(nets)}/{seeds} done and in the target "
                  f"shape; after done: {figures}", flush=True)
            for line in missed:
                print(f"    {line}", flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", default=[str(EIGHT)])
    parser.add_argument("--world", choices=("lattice", "physics"), default="lattice")
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--reverse-seeds", type=int, default=20)
    parser.add_argument("--losses", default="0,0.1,0.2,0.3")
    parser.add_argument("--duration", type=float, default=30.0)
    parser.add_argument("--parallel", action="store_true", help="sequential against parallel steps")
    parser.add_argument("--rollback", action="store_true", help="one step failing at random, with rollback")
    parser.add_argument("--overlap", action="store_true",
                        help="which neighbouring steps could run in parallel, and what it would save")
    parser.add_argument("--crawl", action="store_true",
                        help="car_to_snake in physics: the distance moved once the sequence is done")
    parser.add_argument("--case", default="",
                        help="with --rollback or --parallel: only the cases whose title holds this")
    args = parser.parse_args()
    if args.parallel:
        main_parallel(args)
    elif args.rollback:
        main_rollback(args)
    elif args.crawl:
        main_crawl(args)
    elif args.overlap:
        main_overlap(args)
    else:
        main_default(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
