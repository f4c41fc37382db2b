"""``rdcd simulate FILE [--config car7] [--world physics|lattice] [--obstacle wall:1.0] ...``

Compiles FILE, runs it on a simulated ATRON robot and prints a summary; optionally writes a JSON
report, a top-view plot and an animated GIF. Exit status: 0 ran, 1 the program has errors,
2 bad options, an unusable configuration or an I/O error.
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import functools
import json
import os
import sys
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from sim.config import MAX_RANDOM, MAX_SNAKE
    from sim.quiet import import_pybullet

    import_pybullet()  # before sim.obstacles: its banner kept off the terminal
    from sim.obstacles import MAX_OBSTACLE_M

    parser.add_argument("file", metavar="FILE", help="the RDCD program")
    parser.add_argument("--config", default="car7",
                        help="shipped configuration (car7, car11, car8-cyclic, car17-wide), snakeN with "
                             f"N = 1..{MAX_SNAKE} in the lattice world, 1..{physics_snake_max()} in the "
                             f"physics world, randomN-seedS (N = 1..{MAX_RANDOM} modules grown from seed S, "
                             "as in rdcd sweep) or a JSON file (default: car7)")
    parser.add_argument("--world", choices=("physics", "lattice"), default="physics",
                        help="PyBullet physics (default) or the physics-free lattice")
    parser.add_argument("--obstacle", default="wall:1.0", metavar="SPEC",
                        help="none, wall:D (a wall across the path D m ahead of the driver) or box:X,Y,W,L "
                             f"(metres, each at most {MAX_OBSTACLE_M:g}; default: wall:1.0)")
    parser.add_argument("--duration", type=float, default=60.0, metavar="S",
                        help=f"simulated seconds, more than 0 and at most {MAX_DURATION_S:g} (default: 60)")
    parser.add_argument("--seed", type=int, default=0, help="seed of every random choice (default: 0)")
    parser.add_argument("--packet-loss", type=float, default=0.0, metavar="P",
                        help="probability that an IR packet is lost, 0..1 (default: 0)")
    parser.add_argument("--report", metavar="OUT.json", help="write the JSON report to this file")
    parser.add_argument("--plot", metavar="OUT.png",
                        help="write a top-view plot to this file; its extension names the format "
                             "(.png if it has none; also .pdf, .svg, .jpg, ...)")
    parser.add_argument("--record", metavar="OUT.gif",
                        help="write an animated GIF to this file (.gif added if it has no extension; "
                             "physics world)")
    parser.add_argument("--gui", action="store_true", help="show PyBullet's window (needs an X display)")
    from sim.replay.cli import add_argument as add_replay

    add_replay(parser)

    parser.add_argument("--change", action="append", default=[], metavar="T:WHAT",
                        help="an outside change at time T: 'T:detach ID', 'T:attach ID at X,Y,Z [AXIS] "
                             "[rot R] [mirrored]' or 'T:stop ID' (e.g. 20s:detach 3); repeatable")
    parser.add_argument("--changes", metavar="FILE",
                        help="outside changes from a file, one per line as for --change (# comments)")
    parser.add_argument("--reverse-sequence", metavar="NAME", default=None,
                        help="run the program's sequence NAME backwards (the undo of each step, in "
                             "reverse order), on the robot as the run forward from --config leaves it: its "
                             "end shape, each module keeping the coordinates it learned at the start "
                             "(docs/reconfiguration.md)")
    parser.add_argument("--vm", choices=("default", "original"), default="default",
                        help="VM profile of every module: this project's DCD-VM (default) or the original "
                             "ATRON firmware with its limits and quirks (docs/vm.md)")
    parser.add_argument("--target", choices=("default", "original"), default=None,
                        help="compile the program for this target (default: the one --vm names)")


MAX_DURATION_S = 3600.0


@functools.cache
def physics_snake_max() -> int:
    """The longest snakeN the physics world builds (PyBullet's links per body)."""
    from sim.config import MAX_SNAKE, snake
    from sim.quiet import import_pybullet

    import_pybullet()
    from sim.robot import MAX_LINKS, rigid_part_count

    # a snake of n modules has n + 1 rigid parts: start near the answer, check it for real
    n = min(MAX_SNAKE, MAX_LINKS)
    while n > 1 and rigid_part_count(snake(n)) + 1 > MAX_LINKS:
        n -= 1
    return n


def _fail(message: str) -> int:
    print(f"rdcd simulate: {message}", file=sys.stderr)
    return 2


def check_options(args: argparse.Namespace) -> str | None:
    from sim.quiet import import_pybullet

    import_pybullet()
    from sim.obstacles import ObstacleError, parse_obstacle

    if not 0 < args.duration <= MAX_DURATION_S:
        return f"--duration must be more than 0 and at most {MAX_DURATION_S:g} seconds, not {args.duration:g}"
    if not 0.0 <= args.packet_loss <= 1.0:
        return f"--packet-loss must be in 0..1, not {args.packet_loss:g}"
    try:
        parse_obstacle(args.obstacle)
    except ObstacleError as e:
        return str(e)
    if args.world == "lattice" and (args.gui or args.record is not None):
        return "--gui and --record need the physics world"
    if args.gui:
        return _display_problem()
    return None


def _display_problem() -> str | None:
    """Why PyBullet could not open its window: asked of the X library first, because PyBullet's
    GUI ends the whole process (status 1, no message) when it cannot."""
    if not sys.platform.startswith("linux"):
        return None  # PyBullet uses the system's own windows there
    display = os.environ.get("DISPLAY", "")
    if not display:
        return "--gui needs an X display (DISPLAY is not set); run without --gui or use --record"
    library = ctypes.util.find_library("X11")
    if library is None:
        return "--gui needs the X11 library (libX11), which is not installed; use --record instead"
    try:
        x11 = ctypes.CDLL(library)
        x11.XOpenDisplay.restype = ctypes.c_void_p
        x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
        x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
        handle = x11.XOpenDisplay(display.encode("utf-8", "replace"))
    except (OSError, AttributeError):
        return None  # cannot ask: let PyBullet try
    if not handle:
        return (f"--gui: cannot open the X display {display!r} (DISPLAY); "
                "run without --gui or use --record")
    x11.XCloseDisplay(handle)
    return None


def _output_paths(args: argparse.Namespace) -> list[tuple[str, str]]:
    """(option, path) of every file the run will write, the format of each checked, a missing
    extension added (the path printed at the end is the one written). InputError if one is bad."""
    outputs = []
    if args.report is not None:
        outputs.append(("--report", args.report))
    if args.plot is not None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        # pgf is LaTeX source and needs a TeX installation to be written: not a picture format
        formats = sorted(set(FigureCanvasAgg.get_supported_filetypes()) - {"pgf"})
        args.plot = _with_format("--plot", args.plot, formats, "png")
        outputs.append(("--plot", args.plot))
    if args.record is not None:
        args.record = _with_format("--record", args.record, ["gif"], "gif")
        outputs.append(("--record", args.record))
    if getattr(args, "replay", None) is not None:
        from sim.replay.cli import ACCEPTED

        args.replay = _with_format("--replay", args.replay, ACCEPTED, "html")
        outputs.append(("--replay", args.replay))
    return outputs


def _with_format(option: str, path: str, accepted: list[str], default: str) -> str:
    from rdcd_core.inputs import InputError

    if not path or path.endswith(("/", os.sep)):
        return path  # check_outputs says what is wrong with it
    suffix = Path(path).suffix
    if not suffix:  # /dev/stdout and the like are written as named (in the default format)
        return path if os.path.exists(path) and not os.path.isfile(path) else f"{path}.{default}"
    if suffix[1:].lower() not in accepted:
        raise InputError(f"{option} {path}: unknown format {suffix!r} "
                         f"(accepted: {', '.join('.' + a for a in accepted)})")
    return path


def _physics_problem(structure) -> str | None:  # noqa: ANN001
    from sim.robot import MAX_LINKS, rigid_part_count

    parts = rigid_part_count(structure)
    if parts + 1 <= MAX_LINKS:
        return None
    return (f"{structure.name or 'the structure'}: the physics world cannot build it: {parts} rigid parts, "
            f"PyBullet takes at most {MAX_LINKS - 1} in one body (a snake of at most {physics_snake_max()} "
            "modules); use --world lattice")


def _sequence_end(path: str, name: str, config: str):  # noqa: ANN202 - Trace | str
    """The checker's run of sequence ``name`` forward from ``config`` (the shape it ends in, and
    what each module knows of its place there); a one-line reason when it cannot be known."""
    from rdcd_core.frontend import check_text
    from rdcd_core.inputs import InputError, read_source

    try:
        text = read_source(path)
    except InputError as e:
        return str(e)
    result = check_text(text, config=config)
    names = [s.name.text for s in result.program.sequences]
    if name not in names:
        return (f"--reverse-sequence {name}: the program has no sequence of that name "
                f"(its sequences: {', '.join(names) or 'none'})")
    trace = result.traces.get(names.index(name))
    if trace is None or trace.final is None:
        return (f"--reverse-sequence {name}: the sequence cannot be run forward from {config}, so "
                f"the shape it ends in is not known (see rdcd check --config {config} {path})")
    return trace


def _sequence_lines(path: str, report: dict, reverse: str | None) -> list[str]:
    """How far each sequence of the program got: the progress every module ended with
    (docs/reconfiguration.md), so that a run that ran out of time, or lost every packet, says so."""
    from rdcd_core.inputs import InputError, read_source
    from rdcd_core.sequences.check import steps_of
    from rdcd_core.sequences.progress import done_value, is_rollback, rolled_back_value, steps_done
    from rdcd_core.syntax import parse

    try:
        program = parse(read_source(path)).program
    except InputError:
        return []
    lines = []
    for sequence in program.sequences:
        name, steps = sequence.name.text, sum(1 for _ in steps_of(sequence))
        values = [m.get("final_state", {}).get(name) for m in report.get("modules", [])]
        values = [v for v in values if isinstance(v, int)]
        if not values:
            continue
        rollback = is_rollback(sequence)
        low, high = min(values), max(values)
        way = " backwards" if reverse == name else ""
        if rollback and high > steps:  # progress.undo_value: 2n - 1 - j undoes step j next
            left = rolled_back_value(steps) - high
            state = "rolled back" if low == rolled_back_value(steps) else f"rolling back ({left} to undo)"
        elif low == done_value(sequence):  # the number of steps (progress.progress_plan)
            state = "done"
        else:
            state = f"not done: {steps_done(sequence, high)} of {steps} steps when the run ended"
        lines.append(f"sequence {name}{way}: {state}")
    return lines


def _compile(path: str, target: str, reverse: str | None = None):  # noqa: ANN202 - CompiledProgram | int
    from rdcd_core.cli_check import render_text
    from rdcd_core.cli_compile import compile_text
    from rdcd_core.diagnostics import Severity
    from rdcd_core.inputs import InputError, read_source

    try:
        text = read_source(path)
    except InputError as e:
        return _fail(str(e))
    result, program, diagnostics = compile_text(text, target=target, reverse=reverse)
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
    from rdcd_core.inputs import InputError
    from rdcd_core.outputs import check_outputs
    from sim.config import ConfigError, config_file, load_config
    from vm.lattice.outside import ChangeError

    # everything that can be refused is, before the program is compiled and the world built
    problem = check_options(args)
    if problem:
        return _fail(problem)
    try:
        outputs = _output_paths(args)
        config_path = config_file(args.config)
        structure = load_config(args.config)
        problem = _physics_problem(structure) if args.world == "physics" else None
        if problem:
            return _fail(problem)
        inputs = [("the program", args.file)]
        if config_path is not None:
            inputs.append(("the configuration file", str(config_path)))
        if getattr(args, "changes", None):
            inputs.append(("the changes file", args.changes))
        check_outputs(outputs, inputs)
        changes = outside_changes(args, structure)
    except (ConfigError, InputError, ChangeError) as e:
        return _fail(str(e))
    reverse = getattr(args, "reverse_sequence", None)
    frames: dict = {}
    if reverse is not None:
        ended = _sequence_end(args.file, reverse, args.config)
        if isinstance(ended, str):
            return _fail(ended)
        from rdcd_core.sequences.roles import vm_frames

        # the robot as the forward run leaves it: the end shape, every module holding the frame
        # it learned at the start (docs/reconfiguration.md "Backwards")
        structure, frames = ended.final, vm_frames(ended.learned)
    program = _compile(args.file, args.target or args.vm, reverse)
    if isinstance(program, int):
        return program
    from sim.replay.cli import new_recording
    from sim.robot import RobotError
    from sim.run import Options, simulate

    recording = new_recording(args, program, structure)
    options = Options(world=args.world, config=args.config, obstacle=args.obstacle, duration=args.duration,
                      seed=args.seed, packet_loss=args.packet_loss, gui=args.gui, record=args.record,
                      progress=_progress_bar(), realtime=args.gui, vm=args.vm, recording=recording,
                      outside_changes=changes, frames=frames)
    try:
        report = simulate(program, structure, options)
    except (RobotError, RuntimeError) as e:  # an unbuildable structure; no window for --gui
        return _fail(str(e))
    except OSError as e:  # writing --record
        return _fail(f"cannot write {args.record}: {_why(e)}")
    from sim.report import summary

    # the files first: a closed standard output must not cost the user the run's results
    written, problem = _write_outputs(args, report, structure)
    if recording is not None and problem is None:
        from sim.replay.cli import write as write_replay

        try:
            written.append(write_replay(args, recording, program, structure, report))
        except OSError as e:
            problem = f"--replay {args.replay}: cannot write: {_why(e)}"
    print(summary(report))
    for line in _sequence_lines(args.file, report, reverse):
        print(line)
    for line in written:
        print(line)
    return _fail(problem) if problem else 0


def outside_changes(args: argparse.Namespace, structure) -> list:  # noqa: ANN001
    """The --change options and the --changes file, parsed and checked against the structure and
    the duration (``ChangeError`` / ``InputError``, one line)."""
    from rdcd_core.inputs import InputError, describe_os_error, read_regular
    from vm.lattice.outside import ChangeError, parse_all, validate

    texts = list(getattr(args, "change", None) or [])
    path = getattr(args, "changes", None)
    if path:
        try:
            data = read_regular(path)
        except OSError as e:
            raise InputError(f"--changes {path}: cannot read: {describe_os_error(e)}") from None
        if len(data) > 1_000_000:
            raise ChangeError(f"--changes {path}: {len(data)} bytes; a changes file has at most 1 MB")
        try:
            texts.append(data.decode("utf-8-sig"))
        except UnicodeDecodeError as e:
            raise ChangeError(f"--changes {path}: not UTF-8 text (byte {e.start})") from None
    changes = parse_all(texts)
    if changes and args.world == "physics" and not physics_takes_changes():
        raise ChangeError("--change: this build's physics world does not take outside changes yet; "
                          "use --world lattice")
    validate(changes, structure, args.duration)
    return changes


def physics_takes_changes() -> bool:
    import inspect

    from sim.world import PhysicsWorld

    return "changes" in inspect.signature(PhysicsWorld.__init__).parameters


def _why(error: OSError) -> str:
    from rdcd_core.inputs import describe_os_error

    return describe_os_error(error)


def _write_outputs(args: argparse.Namespace, report: dict, structure) -> tuple[list[str], str | None]:  # noqa: ANN001
    """Writes --report and --plot (--record is written by the run): what to print, and the problem."""
    from rdcd_core.outputs import write_atomically

    written = [f"animation: {args.record}"] if args.record is not None else []
    option, path = "--report", args.report
    try:
        if args.report is not None:
            write_atomically(args.report, json.dumps(report, indent=1) + "\n")
            written.append(f"report: {args.report}")
        if args.plot is not None:
            from sim.plot import plot_report

            option, path = "--plot", args.plot
            plot_report(report, structure, args.plot)
            written.append(f"plot: {args.plot}")
    except OSError as e:
        return written, f"{option} {path}: cannot write: {_why(e)}"
    return written, None
