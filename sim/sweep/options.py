"""The simulate options a sweep may fix or vary: read from ``rdcd simulate``'s own parser.

One source of truth: a sweep run is exactly a ``rdcd simulate`` run, so the option names, flags,
types, choices and defaults are those of ``sim.cli_simulate``; only options that ``sim.run.Options``
carries to the simulation (not outputs such as ``--plot``) can be swept.
"""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass
from functools import cache
from typing import Any


@dataclass(frozen=True)
class OptionSpec:
    name: str  # the key in an experiment file and the attribute of sim.run.Options
    flag: str  # --packet-loss
    kind: type  # str, int or float
    default: Any
    choices: tuple[Any, ...] | None


@cache
def _parser() -> argparse.ArgumentParser:
    from sim import cli_simulate

    parser = argparse.ArgumentParser(add_help=False)
    cli_simulate.add_arguments(parser)
    return parser


@cache
def sweepable() -> dict[str, OptionSpec]:
    from sim.quiet import import_pybullet

    import_pybullet()  # sim.run imports it, and its banner must not reach the terminal
    from sim.run import Options

    parser = _parser()
    carried = {f.name for f in dataclasses.fields(Options)} - {"gui", "record", "progress", "realtime"}
    specs = {}
    for action in parser._actions:  # noqa: SLF001 - the public way to read a parser's options
        if action.dest not in carried or not action.option_strings:
            continue
        kind = action.type if action.type in (int, float) else str
        specs[action.dest] = OptionSpec(action.dest, action.option_strings[0], kind, action.default,
                                        tuple(action.choices) if action.choices else None)
    return specs


def defaults() -> dict[str, Any]:
    return {name: spec.default for name, spec in sweepable().items()}


def simulate_argv(program: str, values: dict[str, Any]) -> list[str]:
    """The ``rdcd simulate`` arguments that replay a run with these option values."""
    argv = ["simulate", program]
    for name, spec in sweepable().items():
        value = values.get(name, spec.default)
        argv += [spec.flag, number_text(value) if isinstance(value, float) else str(value)]
    for change in (values.get("changes") or "").split(";"):  # an experiment's outside changes
        if change.strip():
            argv += ["--change", change.strip()]
    return argv


def number_text(value: float) -> str:
    """The shortest text that reads back as the same float (60.0 -> "60", 0.1 -> "0.1")."""
    return str(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)


def check_values(values: dict[str, Any]) -> str | None:
    """``rdcd simulate``'s own checks of the option values (ranges, obstacle syntax), or None."""
    from sim.cli_simulate import check_options

    every = {a.dest: a.default for a in _parser()._actions}  # noqa: SLF001
    namespace = argparse.Namespace(**{**every, **values, "gui": False, "record": None,
                                      "report": None, "plot": None})
    return check_options(namespace)


def compile_like_simulate(text: str, vm: str | None):  # noqa: ANN201 - check result, program, diagnostics
    """Compile as ``rdcd simulate`` does: for the target its ``--vm`` option names (None: a
    simulate without that option, which compiles for the default target)."""
    from rdcd_core.cli_compile import compile_text

    return compile_text(text) if vm is None else compile_text(text, target=vm)
