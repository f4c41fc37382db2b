"""Configuration files and generators: shipped cars as in docs/simulator.md, one-line ConfigErrors,
valid generated structures."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim.config import (
    ConfigError,
    load_config,
    random_structure,
    shipped_names,
    snake,
    structure_from_json,
    structure_to_json,
)
from vm import navigation
from vm.lattice.geometry import free_spin_axis
from vm.lattice.structure import Structure

NS, EW, UD = navigation.NORTH_SOUTH, navigation.EAST_WEST, navigation.UP_DOWN

CAR7 = {(0, 0, 0): NS, (0, 1, -1): UD, (0, -1, -1): UD, (1, 1, -2): EW, (-1, 1, -2): EW,
        (1, -1, -2): EW, (-1, -1, -2): EW}


def _places(s: Structure) -> dict[tuple[int, int, int], int]:
    return {m.position: m.axis for m in s.modules.values()}


def _shift(places: dict, dx: int) -> dict:
    return {(x + dx, y, z): a for (x, y, z), a in places.items()}


def test_shipped_configs_match_the_table() -> None:
    assert {"car7", "car11", "car8-cyclic", "car17-wide"} <= set(shipped_names())
    assert _places(load_config("car7")) == CAR7
    car11 = dict(CAR7) | {(0, -2, 0): NS, (0, -3, -1): UD, (1, -3, -2): EW, (-1, -3, -2): EW}
    assert _places(load_config("car11")) == car11
    assert _places(load_config("car8-cyclic")) == CAR7 | {(1, -1, 0): EW}
    bridge = {(1, 1, 0): EW, (2, 0, 0): NS, (3, 1, 0): EW}
    assert _places(load_config("car17-wide")) == CAR7 | _shift(CAR7, 4) | bridge


@pytest.mark.parametrize("name", ["car7", "car11", "car8-cyclic", "car17-wide"])
def test_expected_roles_and_forward_sensors(name: str) -> None:
    s = load_config(name)
    assert s.entry == 0 and set(s.expected_roles) == set(s.modules)
    for mid, spec in s.modules.items():
        role = s.expected_roles[mid]
        ports = s.neighbours(mid)
        if spec.axis == UD:
            assert role == "Axle"
        elif spec.axis == EW and len(ports) == 1:
            # the program: a wheel connected EAST is a RightWheel, connected WEST a LeftWheel
            (port,) = ports
            east = s.physical_direction(mid, port)[0] > 0
            assert role == ("RightWheel" if east else "LeftWheel")
            if spec.position[1] > 0:
                watched = 5 if role == "RightWheel" else 1
                for sensor in (1, 5):  # both face forward
                    assert s.physical_direction(mid, sensor)[1] > 0
                # the watched sensor sits on the hemisphere held by the axle, not the spinning one
                assert spec.mount.virtual_of(watched) // 4 == spec.mount.virtual_of(port) // 4
        else:
            assert role is None


@pytest.mark.parametrize("name", ["car7", "car11", "car8-cyclic", "car17-wide"])
def test_wheels_roll_the_car_north(name: str) -> None:
    """RightWheel turns +1, LeftWheel -1 (the program): every free hemisphere must turn about
    -x, so that the car rolls towards +y."""
    s = load_config(name)
    for mid, role in s.expected_roles.items():
        if role in ("RightWheel", "LeftWheel"):
            spec = s.modules[mid]
            speed = 1 if role == "RightWheel" else -1
            assert free_spin_axis(spec.axis, spec.mount, s.free_hemisphere(mid), speed) == (-1, 0, 0)


def test_snake() -> None:
    s = snake(9)
    assert len(s.modules) == 9 and len(s.links()) == 8
    assert [m.axis for m in s.modules.values()] == [NS, EW] * 4 + [NS]
    assert all(m.position[2] == 0 for m in s.modules.values())
    assert load_config("snake5").name == "snake5"
    assert load_config("car7.json").name == "car7"
    with pytest.raises(ConfigError):
        snake(0)


@given(st.integers(1, 60), st.integers(0, 2**32), st.booleans())
def test_random_structures_are_valid_and_deterministic(n: int, seed: int, explicit: bool) -> None:
    s = random_structure(n, seed, explicit_connections=explicit)
    assert len(s.modules) == n
    assert structure_to_json(s) == structure_to_json(random_structure(n, seed, explicit_connections=explicit))
    again = structure_from_json(json.loads(json.dumps(structure_to_json(s))))
    assert again.links() == s.links()


def test_random_structures_vary() -> None:
    shapes = {frozenset(_places(random_structure(12, seed))) for seed in range(10)}
    assert len(shapes) == 10


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "bad.json"
    path.write_text(text)
    return path


GOOD_MODULES = [{"id": 0, "position": [0, 0, 0], "axis": "NS"},
                {"id": 1, "position": [0, 1, -1], "axis": "UD"}]


@pytest.mark.parametrize("change, expected", [
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [0, 1, -1], "axis": "UD"}]},
     "module 2 at (0, 1, -1): place already taken by module 1"),
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [1, 0, 0], "axis": "NS"}]},
     "module 2 at (1, 0, 0): axis NS needs x, y, z all even"),
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [6, 6, 6], "axis": "NS"}]},
     "module 2 at (6, 6, 6): not connected to the entry module 0"),
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [1, 1, 0], "axis": "XY"}]},
     "module 2 at (1, 1, 0): unknown axis 'XY'"),
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [1, 1], "axis": "EW"}]},
     'module 2: "position" must be a list of three integers'),
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [1, 1, 0], "axis": "EW", "postion": 1}]},
     "module 2: unknown field 'postion'"),
    ({"modules": GOOD_MODULES + [{"id": 2, "position": [1, 1, 0], "axis": "EW",
                                  "mount": {"rotation": 5}}]},
     'module 2 at (1, 1, 0): "mount" must be'),
    ({"modules": GOOD_MODULES + [{"id": "two", "position": [1, 1, 0], "axis": "EW"}]},
     'modules[2]: "id" must be an integer'),
    ({"modules": []}, '"modules" must be a non-empty list'),
    ({"connections": [[0]]}, '"connections" must be a list of [id, id] pairs'),
    ({"entry": 1}, "module 1 at (0, 1, -1): the entry module defines the frame"),
    ({"colour": "red"}, "top level: unknown field 'colour'"),
])
def test_bad_fields_give_one_line(tmp_path: Path, change: dict, expected: str) -> None:
    data = {"name": "t", "entry": 0, "modules": GOOD_MODULES} | change
    path = _write(tmp_path, json.dumps(data))
    with pytest.raises(ConfigError) as info:
        load_config(path)
    assert str(info.value) == f"{path}: {expected}" or str(info.value).startswith(f"{path}: {expected}")
    assert "\n" not in str(info.value)


def test_bad_json_and_missing_file(tmp_path: Path) -> None:
    path = _write(tmp_path, '{"modules": [\n  {"id": 0,}\n]}')
    with pytest.raises(ConfigError, match=r"bad.json: invalid JSON at line 2 column"):
        load_config(path)
    with pytest.raises(ConfigError, match="nosuch: no such configuration file.*car7"):
        load_config("nosuch")
    with pytest.raises(ConfigError, match="the top level must be a JSON object"):
        load_config(_write(tmp_path, "[1, 2]"))


def test_saved_structure_loads_back(tmp_path: Path) -> None:
    s = load_config("car17-wide")
    path = tmp_path / "copy.json"
    path.write_text(json.dumps(structure_to_json(s, "a copy")))
    again = load_config(path)
    assert again.links() == s.links() and again.expected_roles == s.expected_roles
