"""Configuration files (sim/configs/*.json) and generated structures, loaded into a ``Structure``.

``load_config`` accepts a path, a shipped name (``car7``, ``car11``, ``car8-cyclic``,
``car17-wide``), ``snakeN`` or ``randomN-seedS`` (the names ``rdcd sweep`` takes too); every
problem becomes a ``ConfigError`` with one line naming the file and, where it applies, the
offending module. The format is described in
sim/configs/README.md.
"""

from __future__ import annotations

import json
import os
import random
import re
import stat
from pathlib import Path
from typing import Any

from rdcd_core.inputs import describe_os_error, read_regular
from vm import navigation
from vm.lattice.mount import ALL_MOUNTS, IDENTITY, Mount
from vm.lattice.structure import ModuleSpec, Structure, StructureError, make_structure

CONFIG_DIR = Path(__file__).resolve().parent / "configs"
MAX_SNAKE = 128  # the lattice world's limit; the physics world's is lower (sim.cli_simulate)
MAX_RANDOM = 1000  # modules of a randomN-seedS structure
GENERATED = re.compile(r"snake([0-9]+)|random([0-9]+)-seed([0-9]+)")
_TOP_FIELDS = {"name", "about", "entry", "modules", "connections"}
_MODULE_FIELDS = {"id", "position", "axis", "mount", "role_expected"}


class ConfigError(ValueError):
    """A configuration that cannot be used; the message is one line."""


def shipped_names() -> list[str]:
    return sorted(p.stem for p in CONFIG_DIR.glob("*.json"))


def config_file(name_or_path: str | Path) -> Path | None:
    """The file ``load_config`` reads for ``name_or_path`` (None for the generated ``snakeN`` and
    ``randomN-seedS``); a ``ConfigError`` if there is none. A path is used as given (a file of
    that name wins over a generated structure); a bare name is a shipped configuration."""
    text = str(name_or_path)
    try:
        info = os.stat(text) if text else None
    except FileNotFoundError:
        info = None
    except OSError as e:  # a loop of links, a name too long: said the way every command says it
        raise ConfigError(f"cannot read {text}: {describe_os_error(e)}") from None
    except ValueError:
        raise ConfigError(f"{text!r}: a path cannot contain a NUL character") from None
    if info is not None:
        if not stat.S_ISREG(info.st_mode):
            raise ConfigError(f"{text}: not a configuration file (a directory or a special file)")
        return Path(text)
    if GENERATED.fullmatch(text):
        return None
    path = CONFIG_DIR / (text if text.endswith(".json") else f"{text}.json")
    if "/" in text or os.sep in text or not path.is_file():
        raise ConfigError(f"{text or repr(text)}: no such configuration file or shipped configuration "
                          f"(shipped: {', '.join(shipped_names())}, snakeN, randomN-seedS)"
                          f"{_broken_link(text)}")
    return path


def load_config(name_or_path: str | Path) -> Structure:
    path = config_file(name_or_path)
    if path is None:
        return generated(str(name_or_path))
    try:
        # utf-8-sig: a byte order mark is accepted, as in a program
        text = read_regular(str(path)).decode("utf-8-sig")
    except OSError as e:
        raise ConfigError(f"cannot read {path}: {describe_os_error(e)}") from None
    except UnicodeDecodeError as e:
        raise ConfigError(f"{path}: not UTF-8 text (byte {e.start})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as e:
        raise ConfigError(f"{path}: invalid JSON at line {e.lineno} column {e.colno}: {e.msg}") from None
    except RecursionError:
        raise ConfigError(f"{path}: invalid configuration: its JSON is nested too deeply") from None
    except ValueError as e:  # an integer of thousands of digits
        raise ConfigError(f"{path}: invalid JSON: {e}") from None
    return structure_from_json(data, source=str(path), default_name=path.stem)


def generated(name: str) -> Structure:
    """``snakeN`` or ``randomN-seedS``: the structure the name describes."""
    match = GENERATED.fullmatch(name)
    if match is None:
        raise ConfigError(f"{name}: not snakeN or randomN-seedS")
    snake_n, random_n, seed = match.groups()
    if snake_n is not None:
        if len(snake_n) > 6:  # int() refuses 4,300 digits
            raise ConfigError(f"{name}: a snake has 1..{MAX_SNAKE} modules")
        return snake(int(snake_n))
    if len(random_n) > 6:
        raise ConfigError(f"{name}: a random structure has 1..{MAX_RANDOM} modules")
    if len(seed) > 18:  # the seed is any integer; this bound keeps int() and the name short
        raise ConfigError(f"{name}: the seed has at most 18 digits")
    return random_structure(int(random_n), int(seed))


def _broken_link(text: str) -> str:
    return " (a broken symbolic link)" if text and os.path.islink(text) else ""


def structure_from_json(data: Any, *, source: str = "configuration", default_name: str = "") -> Structure:
    try:
        return _build(data, default_name)
    except (ConfigError, StructureError) as e:
        raise ConfigError(f"{source}: {e}") from None


def _build(data: Any, default_name: str) -> Structure:
    if not isinstance(data, dict):
        raise ConfigError("the top level must be a JSON object")
    _no_unknown(data, _TOP_FIELDS, "top level")
    raw = data.get("modules")
    if not isinstance(raw, list) or not raw:
        raise ConfigError('"modules" must be a non-empty list')
    specs, roles = [], {}
    for index, item in enumerate(raw):
        spec, has_role, role = _module(item, index)
        specs.append(spec)
        if has_role:
            roles[spec.id] = role
    entry = data.get("entry", specs[0].id)
    if not _is_int(entry):
        raise ConfigError('"entry" must be a module id (an integer)')
    name = data.get("name", default_name)
    if not isinstance(name, str):
        raise ConfigError('"name" must be a string')
    return make_structure(specs, entry=entry, name=name, connections=_connections(data),
                          expected_roles=roles)


def _module(item: Any, index: int) -> tuple[ModuleSpec, bool, str | None]:
    where = f"modules[{index}]"
    if not isinstance(item, dict):
        raise ConfigError(f"{where}: must be an object")
    mid = item.get("id")
    if not _is_int(mid):
        raise ConfigError(f'{where}: "id" must be an integer')
    where = f"module {mid}"
    _no_unknown(item, _MODULE_FIELDS, where)
    pos = item.get("position")
    if not (isinstance(pos, list) and len(pos) == 3 and all(_is_int(c) for c in pos)):
        raise ConfigError(f'{where}: "position" must be a list of three integers')
    where = f"module {mid} at {tuple(pos)}"
    axis = navigation.AXIS_BY_NAME.get(item.get("axis")) if isinstance(item.get("axis"), str) else None
    if axis is None:
        raise ConfigError(f'{where}: unknown axis {item.get("axis")!r} (use "EW", "NS" or "UD")')
    role = item.get("role_expected")
    if role is not None and not isinstance(role, str):
        raise ConfigError(f'{where}: "role_expected" must be a role name or null')
    return (ModuleSpec(mid, (pos[0], pos[1], pos[2]), axis, _mount(item.get("mount"), where)),
            "role_expected" in item, role)


def _mount(raw: Any, where: str) -> Mount:
    if raw is None:
        return IDENTITY
    if not isinstance(raw, dict) or set(raw) - {"rotation", "mirrored"}:
        raise ConfigError(f'{where}: "mount" must be {{"rotation": 0..3, "mirrored": true|false}}')
    rotation, mirrored = raw.get("rotation", 0), raw.get("mirrored", False)
    if not _is_int(rotation) or rotation not in range(4) or not isinstance(mirrored, bool):
        raise ConfigError(f'{where}: "mount" must be {{"rotation": 0..3, "mirrored": true|false}}')
    return Mount(rotation, mirrored)


def _connections(data: dict[str, Any]) -> list[tuple[int, int]] | None:
    raw = data.get("connections")
    if raw is None:
        return None
    if not isinstance(raw, list) or not all(
            isinstance(p, list) and len(p) == 2 and all(_is_int(i) for i in p) for p in raw):
        raise ConfigError('"connections" must be a list of [id, id] pairs')
    return [(a, b) for a, b in raw]


def _no_unknown(obj: dict[str, Any], allowed: set[str], where: str) -> None:
    unknown = sorted(set(obj) - allowed)
    if unknown:
        raise ConfigError(f"{where}: unknown field {unknown[0]!r} (allowed: {', '.join(sorted(allowed))})")


def _is_int(v: Any) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def structure_to_json(structure: Structure, about: str = "") -> dict[str, Any]:
    """The configuration-file form of a structure (for saving generated structures)."""
    modules = []
    for spec in structure.modules.values():
        item: dict[str, Any] = {"id": spec.id, "position": list(spec.position),
                                "axis": navigation.AXIS_NAMES[spec.axis]}
        if spec.mount != IDENTITY:
            item["mount"] = spec.mount.to_json()
        if spec.id in structure.expected_roles:
            item["role_expected"] = structure.expected_roles[spec.id]
        modules.append(item)
    out: dict[str, Any] = {"name": structure.name, "about": about, "entry": structure.entry,
                           "modules": modules}
    if structure.explicit_connections is not None:
        out["connections"] = sorted(sorted(p) for p in structure.explicit_connections)
    return out


def snake(n: int) -> Structure:
    """N modules in a line along +y on the ground: NS at (0, 2k, 0), EW at (1, 2k+1, 0)."""
    if not 1 <= n <= MAX_SNAKE:
        raise ConfigError(f"snake{n}: a snake has 1..{MAX_SNAKE} modules")
    specs = []
    for i in range(n):
        if i % 2 == 0:
            specs.append(ModuleSpec(i, (0, i, 0), navigation.NORTH_SOUTH))
        else:  # rotation 1: each touching pair joins a male and a female connector
            specs.append(ModuleSpec(i, (1, i, 0), navigation.EAST_WEST, Mount(1, False)))
    return make_structure(specs, entry=0, name=f"snake{n}",
                          expected_roles={i: None for i in range(n)})


def random_structure(n: int, seed: int, *, explicit_connections: bool = False) -> Structure:
    """A random connected valid structure of ``n`` modules grown from the entry module 0 at the
    origin (NS, identity mount); other modules get random mounts. With ``explicit_connections``
    the configuration lists its connections: the growth tree plus each other adjacent pair with
    probability 1/2, so some adjacent modules stay unconnected and cycles still occur."""
    if not 1 <= n <= MAX_RANDOM:
        raise ConfigError(f"random{n}-seed{seed}: a random structure has 1..{MAX_RANDOM} modules")
    rng = random.Random(seed)
    specs = [ModuleSpec(0, (0, 0, 0), navigation.NORTH_SOUTH)]
    taken = {(0, 0, 0): 0}
    tree: list[tuple[int, int]] = []
    while len(specs) < n:
        parent = rng.choice(specs)
        x, y, z, axis, _ = navigation.receiver(*parent.position, parent.axis, rng.randrange(8))
        if (x, y, z) in taken or not all(-100 <= c <= 100 for c in (x, y, z)):
            continue
        spec = ModuleSpec(len(specs), (x, y, z), axis, rng.choice(ALL_MOUNTS))
        taken[spec.position] = spec.id
        specs.append(spec)
        tree.append((parent.id, spec.id))
    connections = None
    if explicit_connections:
        extra = {frozenset((s.id, taken[p[:3]])) for s in specs for p in
                 (navigation.receiver(*s.position, s.axis, v) for v in range(8)) if p[:3] in taken}
        extra -= {frozenset(t) for t in tree}
        connections = tree + [tuple(sorted(p)) for p in sorted(extra, key=sorted) if rng.random() < 0.5]
    return make_structure(specs, entry=0, name=f"random{n}-seed{seed}", connections=connections)
