"""The experiment file (TOML): the program, fixed options, the grid, success criteria, outputs.

Everything is checked before anything runs: unknown keys, wrong types, empty axes, a missing
program or configuration, a program with errors, option values ``rdcd simulate`` would refuse.
Each problem is one ``ExperimentError`` line naming the file and the key. The format is what
``rdcd sweep --init`` writes (sim/sweep/example.toml).
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sim.sweep.grid import Axis, Grid, range_axis
from sim.sweep.options import OptionSpec, check_values, compile_like_simulate, defaults, sweepable
from sim.sweep.rows import CHECKS, METRICS
from sim.sweep.state_checks import HeldBy, StateCheck, parse_held_by, parse_state
from sim.sweep.structure_checks import Shape, StructureCheck, parse_structure, shape_of

TOP_KEYS = ("title", "program", "out", "time_limit_s", "parquet", "run", "grid", "success")
SUCCESS_KEYS = ("checks", "min_turn_deg", "bounds", "state", "held_by", "structure")
RANGE_KEYS = ("from", "to", "step")
DEFAULT_CHECKS = ("roles",)
DEFAULT_MIN_TURN_DEG = 15.0


class ExperimentError(ValueError):
    """An experiment file that cannot be run; the message is one line naming the file and key."""


@dataclass(frozen=True)
class ConfigEntry:
    data: dict[str, Any]  # the configuration's JSON, shipped to the worker with each run
    digest: str
    replay: str  # the `rdcd simulate --config` argument that gives the same structure


@dataclass(frozen=True)
class Experiment:
    path: Path
    title: str
    program_path: Path
    program_text: str
    program_digests: dict[str | None, str]  # by the value of simulate's --vm (None: it has none)
    fixed: dict[str, Any]
    grid: Grid
    configs: dict[str, ConfigEntry]
    checks: tuple[str, ...]
    min_turn_deg: float
    bounds: dict[str, tuple[float | None, float | None]]
    time_limit_s: float
    out: Path | None
    parquet: bool | None
    state: tuple[StateCheck, ...] = ()  # [success.state] (sim/sweep/state_checks.py)
    held_by: tuple[HeldBy, ...] = ()  # [success.held_by]
    structure: tuple[StructureCheck, ...] = ()  # [success.structure] (sim/sweep/structure_checks.py)

    @property
    def size(self) -> int:
        return self.grid.size

    @property
    def option_names(self) -> list[str]:
        return [*sweepable(), CHANGES]

    @property
    def cell_axes(self) -> list[str]:
        """The grid's axes that tell cells apart: all but the seed, which repeats a cell."""
        return [name for name in self.grid.names if name != "seed"]

    def values(self, index: int) -> dict[str, Any]:
        point = self.grid.point(index)
        return {name: point.get(name, self.fixed.get(name)) for name in self.option_names}


def load(path: str | Path) -> Experiment:
    """Read and check an experiment file; ``ExperimentError`` names the first problem."""
    from rdcd_core.inputs import InputError, read_source

    file = Path(path)
    try:
        data = tomllib.loads(read_source(str(file)))
    except InputError as error:
        raise ExperimentError(str(error)) from None
    except tomllib.TOMLDecodeError as error:
        raise ExperimentError(f"{file}: not valid TOML: {error}") from None
    return _Reader(file).experiment(data)


class _Reader:
    def __init__(self, file: Path) -> None:
        self.file = file
        self.base = file.resolve().parent
        self.states: set[str] = set()  # of the program, for [success.state]
        self.roles: set[str] = set()

    def fail(self, key: str, problem: str) -> ExperimentError:
        return ExperimentError(f"{self.file}: {key}: {problem}")

    def experiment(self, data: dict[str, Any]) -> Experiment:
        self.known(data, TOP_KEYS, "")
        program_path, text = self.program(data)
        run = self.table(data, "run")
        grid_table = self.table(data, "grid")
        specs = sweepable()
        self.known(run, (*specs, CHANGES), "run.")
        self.known(grid_table, (*specs, CHANGES), "grid.")
        if not grid_table:
            raise self.fail("grid", "empty: give at least one axis, e.g. seed = { from = 1, to = 10 }")
        fixed = {**defaults(), CHANGES: ""}
        for name, raw in run.items():
            if name in grid_table:
                raise self.fail(f"run.{name}", "also an axis of [grid]: give it in one place")
            fixed[name] = (self.changes(f"run.{name}", raw) if name == CHANGES
                           else self.value(f"run.{name}", raw, specs[name]))
        axes = tuple(self.changes_axis(raw) if name == CHANGES else self.axis(name, raw, specs[name])
                     for name, raw in grid_table.items())
        for axis in axes:
            fixed.pop(axis.name, None)
        self.check_values({k: v for k, v in fixed.items() if k != CHANGES},
                          tuple(a for a in axes if a.name != CHANGES))
        vms = next((a.values for a in axes if a.name == "vm"), None) or (fixed.get("vm"),)
        digests = {vm: self.compiled(program_path, text, vm) for vm in dict.fromkeys(vms)}
        configs = self.configs(fixed, axes)
        self.check_changes(fixed, axes, configs)
        checks, min_turn, bounds = self.success(data)
        state, held_by = self.final_state(data)
        structure, problem = parse_structure(self.table(data, "success").get("structure", {}), self.shape)
        if problem is not None:
            raise ExperimentError(f"{self.file}: {problem}")
        return Experiment(self.file, self.string(data, "title", self.file.stem), program_path, text, digests,
                          fixed, Grid(axes), configs, checks, min_turn, bounds,
                          self.time_limit(data, fixed, axes), self.out(data), self.parquet(data),
                          state, held_by, structure)

    def known(self, table: dict[str, Any], allowed: tuple[str, ...], prefix: str) -> None:
        for key in table:
            if key not in allowed:
                raise self.fail(f"{prefix}{key}", f"unknown key (known: {', '.join(allowed)})")

    def table(self, data: dict[str, Any], key: str) -> dict[str, Any]:
        value = data.get(key, {})
        if not isinstance(value, dict):
            raise self.fail(key, f"must be a table ([{key}]), not {_kind(value)}")
        return value

    def string(self, data: dict[str, Any], key: str, default: str) -> str:
        value = data.get(key, default)
        if not isinstance(value, str):
            raise self.fail(key, f"must be a string, not {_kind(value)}")
        return value

    def program(self, data: dict[str, Any]) -> tuple[Path, str]:
        from rdcd_core.inputs import InputError, read_source

        if "program" not in data:
            raise self.fail("program", "missing: name the RDCD program, e.g. program = \"obstacle.rdcd\"")
        path = self.base / self.string(data, "program", "")
        try:
            text = read_source(str(path))
        except InputError as error:
            raise self.fail("program", str(error)) from None
        return path, text

    def compiled(self, path: Path, text: str, vm: str | None) -> str:
        """The digest of the program as compiled for ``vm``; its first error fails the file."""
        from rdcd_core.cli_check import render_text
        from rdcd_core.diagnostics import Severity

        result, program, diagnostics = compile_like_simulate(text, vm)
        errors = [d for d in diagnostics if d.severity is Severity.ERROR]
        if program is None or errors:
            first = (render_text(str(path), result, errors[0]).splitlines()[0] if errors
                     else "it does not compile")
            more = f" (and {len(errors) - 1} more; rdcd check shows them)" if len(errors) > 1 else ""
            target = f" (for --vm {vm})" if vm not in (None, "default") else ""
            raise self.fail("program", f"the program has errors{target}: {first}{more}")
        self.states.update(s.name for s in program.states)
        self.roles.update(r.name for r in program.roles)
        return program_digest(program)

    def value(self, key: str, raw: Any, spec: OptionSpec) -> Any:
        if spec.kind is float and isinstance(raw, (int, float)) and not isinstance(raw, bool):
            value: Any = float(raw)
        elif spec.kind is int and isinstance(raw, int) and not isinstance(raw, bool):
            value = raw
        elif spec.kind is str and isinstance(raw, str):
            value = raw
        else:
            raise self.fail(key, f"must be {_kind_name(spec.kind)}, not {_kind(raw)}")
        if spec.choices and value not in spec.choices:
            raise self.fail(key, f"{value!r} is not one of {', '.join(map(str, spec.choices))}")
        return value

    def axis(self, name: str, raw: Any, spec: OptionSpec) -> Axis:
        key = f"grid.{name}"
        if isinstance(raw, list):
            if not raw:
                raise self.fail(key, "empty list: the grid would have no runs")
            return Axis(name, tuple(self.value(f"{key}[{i}]", v, spec) for i, v in enumerate(raw)))
        if isinstance(raw, dict) and spec.kind in (int, float):
            self.known(raw, RANGE_KEYS, f"{key}.")
            for part in ("from", "to"):
                if part not in raw:
                    raise self.fail(key, f"a range needs 'from' and 'to' (and may give 'step'); "
                                         f"'{part}' is missing")
            start, stop = (self.value(f"{key}.{p}", raw[p], spec) for p in ("from", "to"))
            step = self.value(f"{key}.step", raw.get("step", 1), spec)
            if step <= 0:
                raise self.fail(f"{key}.step", f"must be positive, not {step}")
            axis = range_axis(name, start, stop, step, spec.kind is int)
            if len(axis) == 0:
                raise self.fail(key, f"empty range: 'to' ({stop}) is below 'from' ({start})")
            return axis
        shape = "a list" if spec.kind is str else "a list or a range { from = ..., to = ..., step = ... }"
        raise self.fail(key, f"must be {shape}, not {_kind(raw)}")

    def changes(self, key: str, raw: Any) -> str:
        """One set of outside changes: a change text or a list of them, as ``rdcd simulate --change``
        takes them; kept as one string, the changes joined by "; " ("" for none)."""
        from vm.lattice.outside import ChangeError, parse_all

        texts = [raw] if isinstance(raw, str) else raw
        if not isinstance(texts, list) or not all(isinstance(t, str) for t in texts):
            what = "a list with other things in it" if isinstance(raw, list) else _kind(raw)
            raise self.fail(key, f"must be a change (\"20s:detach 3\") or a list of change texts, not {what}")
        if any(";" in t or "\n" in t for t in texts):
            raise self.fail(key, "one change per string (no ';' or line breaks in it)")
        try:
            parse_all(texts)
        except ChangeError as error:
            raise self.fail(key, str(error)) from None
        return "; ".join(t.strip() for t in texts if t.split("#", 1)[0].strip())

    def changes_axis(self, raw: Any) -> Axis:
        """[grid] changes: a list of sets of changes; each a change text or a list of texts."""
        key = f"grid.{CHANGES}"
        if not isinstance(raw, list) or not raw:
            raise self.fail(key, "must be a non-empty list of sets of changes, e.g. [[], [\"20s:detach 3\"]]")
        return Axis(CHANGES, tuple(self.changes(f"{key}[{i}]", v) for i, v in enumerate(raw)))

    def check_changes(self, fixed: dict[str, Any], axes: tuple[Axis, ...],
                      configs: dict[str, ConfigEntry]) -> None:
        """Every set of changes against every configuration and the shortest duration (a missing
        module, an occupied cell, a time past the end), as ``rdcd simulate`` checks them."""
        from sim.config import structure_from_json
        from vm.lattice.outside import ChangeError, validate

        axis = next((a for a in axes if a.name == CHANGES), None)
        sets = axis.values if axis is not None else (fixed[CHANGES],)
        key = f"grid.{CHANGES}" if axis is not None else f"run.{CHANGES}"
        durations = next((a.ends() for a in axes if a.name == "duration"), [fixed.get("duration", 60.0)])
        for i, text in enumerate(sets or ()):
            if not text:
                continue
            changes = parse_changes(text)
            for name, entry in configs.items():
                try:
                    validate(changes, structure_from_json(entry.data, source=name), min(durations))
                except ChangeError as error:
                    where = f"{key}[{i}]" if axis is not None else key
                    raise self.fail(where, f"on {name}: {error}") from None

    def shape(self, name: str) -> Shape:
        """[success.structure] shape: the configuration's cells and latched pairs."""
        from sim.config import structure_from_json

        try:
            entry = self.config("success.structure.shape", name)
        except ExperimentError as error:
            raise ValueError(str(error).split(": ", 2)[-1]) from None
        return shape_of(structure_from_json(entry.data, source=name), name)

    def check_values(self, fixed: dict[str, Any], axes: tuple[Axis, ...]) -> None:
        problem = check_values(fixed)
        if problem:
            raise self.fail("run", problem)
        for axis in axes:
            for value in axis.ends():
                problem = check_values({**fixed, **{a.name: a[0] for a in axes}, axis.name: value})
                if problem:
                    raise self.fail(f"grid.{axis.name}", problem)

    def configs(self, fixed: dict[str, Any], axes: tuple[Axis, ...]) -> dict[str, ConfigEntry]:
        values = next((a.values for a in axes if a.name == "config"), None) or (fixed["config"],)
        key = "grid.config" if any(a.name == "config" for a in axes) else "run.config"
        return {value: self.config(key, value) for value in dict.fromkeys(values)}

    def config(self, key: str, value: str) -> ConfigEntry:
        from sim.config import ConfigError, load_config, structure_to_json

        # a file beside the experiment first; else what `rdcd simulate --config` takes: a path from
        # here, a shipped name, snakeN or randomN-seedS. The run's command names the same.
        beside = self.base / value
        replay = str(beside) if value and beside.is_file() else value
        try:
            structure = load_config(replay)
        except ConfigError as error:
            raise self.fail(key, str(error)) from None
        data = structure_to_json(structure)
        digest = hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()
        return ConfigEntry(data, digest, replay)

    def success(self, data: dict[str, Any]) -> tuple[tuple[str, ...], float, dict]:
        table = self.table(data, "success")
        self.known(table, SUCCESS_KEYS, "success.")
        checks = table.get("checks", list(DEFAULT_CHECKS))
        if not isinstance(checks, list) or not all(isinstance(c, str) for c in checks):
            raise self.fail("success.checks", f"must be a list of check names ({', '.join(CHECKS)})")
        for i, name in enumerate(checks):
            if name not in CHECKS:
                raise self.fail(f"success.checks[{i}]",
                                f"unknown check {name!r} (known: {', '.join(CHECKS)})")
        turn = table.get("min_turn_deg", DEFAULT_MIN_TURN_DEG)
        if isinstance(turn, bool) or not isinstance(turn, (int, float)) or not 0 <= turn <= 180:
            raise self.fail("success.min_turn_deg", "must be a number of degrees in 0..180")
        bounds_table = table.get("bounds", {})
        if not isinstance(bounds_table, dict):
            raise self.fail("success.bounds", "must be a table of measure = { min = ..., max = ... }")
        bounds = {}
        for metric, bound in bounds_table.items():
            key = f"success.bounds.{metric}"
            if metric not in METRICS:
                raise self.fail(key, f"unknown measure (known: {', '.join(METRICS)})")
            if not isinstance(bound, dict) or not bound or set(bound) - {"min", "max"} or not all(
                    isinstance(v, (int, float)) and not isinstance(v, bool) for v in bound.values()):
                raise self.fail(key, "must be { min = number } or { max = number } or both")
            bounds[metric] = (bound.get("min"), bound.get("max"))
        return tuple(checks), float(turn), bounds

    def final_state(self, data: dict[str, Any]) -> tuple[tuple[StateCheck, ...], tuple[HeldBy, ...]]:
        table = self.table(data, "success")
        state, problem = parse_state(table.get("state", {}), self.states)
        if problem is None:
            held_by, problem = parse_held_by(table.get("held_by", {}), self.roles)
        if problem is not None:
            raise ExperimentError(f"{self.file}: {problem}")
        return state, held_by

    def time_limit(self, data: dict[str, Any], fixed: dict[str, Any], axes: tuple[Axis, ...]) -> float:
        durations = next((a.ends() for a in axes if a.name == "duration"), [fixed.get("duration", 60.0)])
        default = 60.0 + 10.0 * max(durations)  # a run is normally much faster than real time
        value = data.get("time_limit_s", default)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 7 * 24 * 3600:
            raise self.fail("time_limit_s", "must be a positive number of wall-clock seconds per run")
        return float(value)

    def out(self, data: dict[str, Any]) -> Path | None:
        return self.base / self.string(data, "out", "") if "out" in data else None

    def parquet(self, data: dict[str, Any]) -> bool | None:
        value = data.get("parquet")
        if value is not None and not isinstance(value, bool):
            raise self.fail("parquet", f"must be true or false, not {_kind(value)}")
        return value


CHANGES = "changes"  # the outside changes of a run: one string, changes joined by "; "


def parse_changes(text: str) -> list:
    """The ``OutsideChange`` list of a run's ``changes`` value."""
    from vm.lattice.outside import parse_all

    return parse_all([t for t in text.split(";") if t.strip()])


def program_digest(program: Any) -> str:
    """A hash of everything of a compiled program that a run sees: code, roles, injection order."""
    content = {"fragments": [[f.name, f.kind, f.role, f.code.hex()] for f in program.fragments],
               "roles": [[r.id, r.name, r.kind, list(r.instance_of)] for r in program.roles],
               "injection": list(program.injection), "packet_budget": program.packet_budget}
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode()).hexdigest()


def _kind(value: Any) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "a list",
            dict: "a table"}.get(type(value), type(value).__name__)


def _kind_name(kind: type) -> str:
    return {int: "an integer", float: "a number", str: "a string"}[kind]
