"""``launch``: the arguments checked like ``rdcd simulate``'s options, the program read and checked
by the front end (its errors are the launch's answer: nothing runs), the structure loaded."""

from __future__ import annotations

import argparse
import os
from dataclasses import dataclass
from typing import Any

from rdcd_core.compiler.program import CompiledProgram
from vm.lattice.structure import Structure

DEFAULTS: dict[str, Any] = {"world": "physics", "config": "car7", "obstacle": "wall:1.0", "duration": 60.0,
                            "seed": 0, "packetLoss": 0.0, "vm": "default", "target": None,
                            "stopOnEntry": False, "noDebug": False}


class LaunchError(Exception):
    def __init__(self, message: str, diagnostics: list[dict[str, Any]] | None = None) -> None:
        super().__init__(message)
        self.diagnostics = diagnostics or []  # {"text", "line", "column"} for the debug console


@dataclass
class Launch:
    path: str
    text: str
    program: CompiledProgram
    structure: Structure
    options: Any  # sim.run.Options
    stop_on_entry: bool
    no_debug: bool
    methods: list


def _get(args: dict[str, Any], key: str, kinds: tuple[type, ...], what: str) -> Any:
    value = args.get(key, DEFAULTS[key])
    if value is None and DEFAULTS[key] is None:
        return None
    if isinstance(value, bool) and bool not in kinds or not isinstance(value, kinds):
        raise LaunchError(f"launch: '{key}' must be {what}, not {value!r}")
    return value


def prepare(args: dict[str, Any]) -> Launch:
    from rdcd_core.inputs import InputError, read_source
    from sim.cli_simulate import _physics_problem, check_options
    from sim.config import ConfigError, load_config
    from sim.run import Options

    program_path = args.get("program")
    if not isinstance(program_path, str) or not program_path:
        raise LaunchError("launch: 'program' (the .rdcd file to debug) is missing")
    cwd = args.get("cwd")
    if isinstance(cwd, str) and cwd and not os.path.isabs(program_path):
        program_path = os.path.join(cwd, program_path)
    world = _get(args, "world", (str,), '"physics" or "lattice"')
    if world not in ("physics", "lattice"):
        raise LaunchError(f"launch: 'world' must be \"physics\" or \"lattice\", not {world!r}")
    vm = _get(args, "vm", (str,), '"default" or "original"')
    target = _get(args, "target", (str,), '"default" or "original"')
    for key, value in (("vm", vm), ("target", target)):
        if value is not None and value not in ("default", "original"):
            raise LaunchError(f"launch: '{key}' must be \"default\" or \"original\", not {value!r}")
    try:
        duration = float(_get(args, "duration", (int, float), "a number of seconds"))
        packet_loss = float(_get(args, "packetLoss", (int, float), "a probability 0..1"))
    except OverflowError:
        raise LaunchError("launch: 'duration' and 'packetLoss' must be finite numbers") from None
    namespace = argparse.Namespace(
        duration=duration, packet_loss=packet_loss,
        obstacle=_get(args, "obstacle", (str,), "an obstacle (none, wall:D, box:X,Y,W,L)"),
        world=world, gui=False, record=None)
    seed = _get(args, "seed", (int,), "an integer")
    config = _get(args, "config", (str,), "a configuration name or JSON file")
    stop_on_entry = _get(args, "stopOnEntry", (bool,), "true or false")
    no_debug = _get(args, "noDebug", (bool,), "true or false")
    problem = check_options(namespace)
    if problem:
        raise LaunchError(f"launch: {problem.replace('--packet-loss', 'packetLoss').replace('--', '')}")
    try:
        structure = load_config(config)
    except ConfigError as e:
        raise LaunchError(f"launch: config: {e}") from None
    if world == "physics":
        problem = _physics_problem(structure)
        if problem:
            raise LaunchError(f"launch: {problem}")
    try:
        text = read_source(program_path)
    except InputError as e:
        raise LaunchError(f"launch: {e}") from None
    changes = _changes(args.get("changes", []), structure, namespace)
    program, methods = _compile(program_path, text, target or vm)
    options = Options(world=world, config=config, obstacle=namespace.obstacle, duration=namespace.duration,
                      seed=seed, packet_loss=namespace.packet_loss, vm=vm, outside_changes=changes)
    return Launch(os.path.abspath(program_path), text, program, structure, options, stop_on_entry, no_debug,
                  methods)


def _changes(raw: Any, structure: Structure, namespace: argparse.Namespace) -> list:
    """The launch's "changes": outside changes as ``rdcd simulate --change`` takes them."""
    from sim.cli_simulate import physics_takes_changes
    from vm.lattice.outside import ChangeError, parse_all, validate

    if not isinstance(raw, list) or not all(isinstance(c, str) for c in raw):
        raise LaunchError(f"launch: 'changes' must be a list of strings such as \"20s:detach 3\", "
                          f"not {raw!r}")
    try:
        changes = parse_all(raw)
        if changes and namespace.world == "physics" and not physics_takes_changes():
            raise ChangeError("this build's physics world does not take outside changes yet; use the lattice")
        validate(changes, structure, namespace.duration)
    except ChangeError as e:
        raise LaunchError(f"launch: changes: {e}") from None
    return changes


def _compile(path: str, text: str, target: str) -> tuple[CompiledProgram, list]:
    from debug.code import Method
    from rdcd_core.cli_check import _positions, render_text
    from rdcd_core.cli_compile import compile_text
    from rdcd_core.diagnostics import Severity

    result, program, diagnostics = compile_text(text, target=target)
    errors = [d for d in diagnostics if d.severity is Severity.ERROR]
    if program is None or errors:
        shown = []
        for d in errors:
            line, column, _, _ = _positions(result, d)
            shown.append({"text": render_text(path, result, d), "line": line, "column": column,
                          "path": os.path.abspath(path)})
        first = shown[0]["text"].splitlines()[0] if shown else "it could not be compiled"
        raise LaunchError(f"{path}: {len(errors) or 1} error(s) in the program, nothing runs: {first}", shown)
    methods = []
    model = result.model
    index = result.line_index
    for role_name, role in (model.roles.items() if model is not None else []):
        for name, method in role.methods.items():
            span = getattr(method.decl, "span", None)
            if span is None:
                continue
            lines = (index.line_col(span.start).line + 1, index.line_col(span.end).line + 1)
            methods.append(Method(role_name, name, lines))
    return program, methods
