"""``rdcd simulate FILE [--config car7] [--world physics|lattice] [--obstacle wall:1.0] ...``

Compiles FILE, runs it on a simulated ATRON robot and prints a summary; optionally writes a JSON
report, a top-view plot and an animated GIF. Exit status: 0 ran, 1 the program has errors,
2 bad options, an unusable configuration or an I/O error.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE", help="the RDCD program")
    parser.add_argument("--config", default="car7",
                        help="shipped configuration (car7, car11, car8-cyclic, car17-wide, snakeN) "
                             "or a JSON file (default: car7)")
    parser.add_argument("--world", choices=("physics", "lattice"), default="physics",
                        help="PyBullet physics (default) or the physics-free lattice")
    parser.add_argument("--obstacle", default="wall:1.0", metavar="SPEC",
                        help="none, wall:D (a wall across the path D m ahead of the driver) or box:X,Y,W,L "
                             "(metres; default: wall:1.0)")
    parser.add_argument("--duration", type=float, default=60.0, metavar="S",
                        help="simulated seconds (default: 60)")
    parser.add_argument("--seed", type=int, default=0, help="seed of every random choice (default: 0)")
    parser.add_argument("--packet-loss", type=float, default=0.0, metavar="P",
                        help="probability that an IR packet is lost, 0..1 (default: 0)")
    parser.add_argument("--report", metavar="OUT.json", help="write the JSON report here")
    parser.add_argument("--plot", metavar="OUT.png", help="write a top-view plot here")
    parser.add_argument("--record", metavar="OUT.gif", help="write an animated GIF (physics world)")
    parser.add_argument("--gui", action="store_true", help="show PyBullet's window (needs a display)")
    parser.add_argument("--vm", choices=("default", "original"), default="default",
                        help="VM profile of every module: this project's DCD-VM (default) or the original "
                             "ATRON firmware with its limits and quirks (dcd-vm.md §10)")
    parser.add_argument("--target", choices=("default", "original"), default=None,
                        help="compile the program for this target (default: the one --vm names)")


def _fail(message: str) -> int:
    print(f"rdcd simulate: {message}", file=sys.stderr)
    return 2


def _check_options(args: argparse.Namespace) -> str | None:
    from sim.quiet import import_pybullet

    import_pybullet()
    from sim.obstacles import ObstacleError, parse_obstacle

    if not 0 < args.duration <= 3600:
        return f"--duration must be in (0, 3600] seconds, not {args.duration:g}"
    if not 0.0 <= args.packet_loss <= 1.0:
        return f"--packet-loss must be in 0..1, not {args.packet_loss:g}"
    try:
        parse_obstacle(args.obstacle)
    except ObstacleError as e:
        return str(e)
    if args.world == "lattice" and (args.gui or args.record):
        return "--gui and --record need the physics world"
    if args.gui and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return "--gui needs a display (DISPLAY is not set); run without --gui or use --record"
    for option, path in (("--report", args.report), ("--plot", args.plot), ("--record", args.record)):
        if path and not Path(path).resolve().parent.is_dir():
            return f"{option} {path}: the folder does not exist"
    return None


def _compile(path: str, target: str):  # noqa: ANN202 - CompiledProgram | int
    from rdcd_core.cli_check import render_text
    from rdcd_core.cli_compile import compile_text
    from rdcd_core.diagnostics import Severity
    from rdcd_core.inputs import InputError, read_source

    try:
        text = read_source(path)
    except InputError as e:
        return _fail(str(e))
    result, program, diagnostics = compile_text(text, target=target)
    errors = [d for d in diagnostics if d.severity is Severity.ERROR]
    for diagnostic in errors:
        sys.stderr.write(render_text(path, result, diagnostic))
    if program is None or errors:
        return 1
    return program


def _progress_bar():  # noqa: ANN202
    if not sys.stderr.isatty():
        return None

    def show(done: float, total: float) -> None:
        width = 30
        filled = int(width * done / total)
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done:5.1f}/{total:g} s")
        if done >= total:
            sys.stderr.write("\n")
        sys.stderr.flush()
    return show


def run(args: argparse.Namespace) -> int:
    from sim.config import ConfigError, load_config

    problem = _check_options(args)
    if problem:
        return _fail(problem)
    try:
        structure = load_config(args.config)
    except ConfigError as e:
        return _fail(str(e))
    program = _compile(args.file, args.target or args.vm)
    if isinstance(program, int):
        return program
    from sim.robot import RobotError
    from sim.run import Options, simulate

    options = Options(world=args.world, config=args.config, obstacle=args.obstacle, duration=args.duration,
                      seed=args.seed, packet_loss=args.packet_loss, gui=args.gui, record=args.record,
                      progress=_progress_bar(), realtime=args.gui, vm=args.vm)
    try:
        report = simulate(program, structure, options)
    except (RobotError, RuntimeError) as e:  # an unbuildable structure; no window for --gui
        return _fail(str(e))
    from sim.report import summary

    print(summary(report))
    return _write_outputs(args, report, structure)


def _write_outputs(args: argparse.Namespace, report: dict, structure) -> int:  # noqa: ANN001
    try:
        if args.report:
            Path(args.report).write_text(json.dumps(report, indent=1) + "\n", encoding="utf-8")
            print(f"report: {args.report}")
        if args.plot:
            from sim.plot import plot_report
            plot_report(report, structure, args.plot)
            print(f"plot: {args.plot}")
        if args.record:
            print(f"animation: {args.record}")
    except OSError as e:
        return _fail(f"cannot write: {e}")
    return 0
