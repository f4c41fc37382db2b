"""`rdcd simulate` refuses at the start, in one line, what it cannot do: configurations it cannot
read, ranges a world cannot build, a display it cannot open. Nothing is compiled or run first."""

from __future__ import annotations

import ctypes.util
import json
import re
from pathlib import Path

import pytest

from tests.cli.helpers import assert_clean_failure, rdcd
from tests.conftest import EXAMPLES, ROOT

PROGRAM = str(EXAMPLES / "obstacle_avoidance.rdcd")
CONFIG = (ROOT / "sim" / "configs" / "car7.json").read_text(encoding="utf-8")


def _help_ranges() -> tuple[int, int]:
    """The snakeN ranges --help promises: (lattice world, physics world)."""
    text = " ".join(rdcd("simulate", "--help").stdout.split())
    match = re.search(r"N = 1\.\.(\d+) in the lattice world, 1\.\.(\d+) in the physics world", text)
    assert match, text
    return int(match.group(1)), int(match.group(2))


def test_the_snake_ranges_in_help_are_the_real_limits() -> None:
    lattice, physics = _help_ranges()
    assert physics < lattice
    for world, limit in (("lattice", lattice), ("physics", physics)):
        done = rdcd("simulate", PROGRAM, "--world", world, "--config", f"snake{limit}", "--obstacle", "none",
                    "--duration", "0.1")
        assert done.returncode == 0, (world, done.stderr)
        done = rdcd("simulate", PROGRAM, "--world", world, "--config", f"snake{limit + 1}",
                    "--duration", "0.1")
        assert_clean_failure(done, 2, f"snake{limit + 1}")
        assert done.stdout == ""
        if world == "physics":  # the real limit stated, and the way out
            assert f"at most {physics} modules" in done.stderr and "--world lattice" in done.stderr


@pytest.mark.parametrize("name", ["snake0", "snake" + "9" * 5000, "snake-1"])
def test_impossible_snakes(name: str) -> None:
    done = rdcd("simulate", PROGRAM, "--world", "lattice", "--config", name, "--duration", "0.1")
    assert_clean_failure(done, 2)
    assert "internal error" not in done.stderr


def test_random_structures_are_configurations_of_simulate_too() -> None:
    """The names a sweep takes: randomN-seedS is the structure the sweep builds, by name."""
    from sim.config import load_config, random_structure

    done = rdcd("simulate", PROGRAM, "--world", "lattice", "--config", "random30-seed4", "--duration", "0.5")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("random30-seed4 in the lattice world") and "30 × none" in done.stdout
    assert load_config("random30-seed4") == random_structure(30, 4)
    assert "randomN-seedS" in " ".join(rdcd("simulate", "--help").stdout.split())


@pytest.mark.parametrize("name", ["random0-seed1", "random1001-seed1", "random" + "9" * 5000 + "-seed1",
                                  "random5-seed" + "9" * 5000, "random5-seed-1", "random5"])
def test_impossible_random_structures(name: str) -> None:
    done = rdcd("simulate", PROGRAM, "--world", "lattice", "--config", name, "--duration", "0.1")
    assert_clean_failure(done, 2)
    assert "internal error" not in done.stderr and done.stderr.count("\n") == 1


def test_a_physics_limit_applies_to_configuration_files_too(tmp_path: Path) -> None:
    """A long snake written as a file: the same limit, said before the run."""
    _, physics = _help_ranges()
    n = physics + 1
    modules = [{"id": i, "position": [i % 2, i, 0], "axis": "EW" if i % 2 else "NS"}
               | ({"mount": {"rotation": 1, "mirrored": False}} if i % 2 else {}) for i in range(n)]
    path = tmp_path / "long.json"
    path.write_text(json.dumps({"name": "long", "modules": modules}), encoding="utf-8")
    done = rdcd("simulate", PROGRAM, "--config", str(path), "--duration", "0.1")
    assert_clean_failure(done, 2, "long: the physics world cannot build it", "--world lattice")


def test_a_configuration_with_a_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "bom.json"
    path.write_bytes("\ufeff".encode() + CONFIG.encode("utf-8"))
    done = rdcd("simulate", PROGRAM, "--config", str(path), "--world", "lattice", "--duration", "0.5")
    assert done.returncode == 0, done.stderr
    assert "roles:" in done.stdout


@pytest.mark.parametrize(("content", "words"), [
    ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
    ('{"modules": [' * 50_000 + "]}" * 50_000, "nested too deeply"),
    ('{"entry": ' + "9" * 10_000 + "}", "invalid JSON"),
    ("\ufeff\ufeff{}", "invalid JSON"),
])
def test_hostile_configuration_files_get_one_line(tmp_path: Path, content: str, words: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(content, encoding="utf-8")
    done = rdcd("simulate", PROGRAM, "--config", str(path), "--world", "lattice", "--duration", "0.5")
    assert_clean_failure(done, 2, f"{path}: ", words)
    assert "internal error" not in done.stderr


def test_a_configuration_that_is_not_utf8(tmp_path: Path) -> None:
    path = tmp_path / "latin1.json"
    path.write_bytes('{"name": "\xc4"}'.encode("latin-1"))
    assert_clean_failure(rdcd("simulate", PROGRAM, "--config", str(path)), 2, "not UTF-8")


@pytest.mark.skipif(ctypes.util.find_library("X11") is None, reason="no libX11 to ask")
def test_gui_with_an_unreachable_display_says_so() -> None:
    """PyBullet ends the process (status 1, no message) when its window cannot open: asked first."""
    done = rdcd("simulate", PROGRAM, "--gui", "--duration", "0.5", env={"DISPLAY": ":987"})
    assert_clean_failure(done, 2, "--gui", "cannot open the X display ':987'")
    assert done.stdout == ""


def test_gui_without_any_display_says_so() -> None:
    done = rdcd("simulate", PROGRAM, "--gui", "--duration", "0.5", env={"DISPLAY": ""})
    assert_clean_failure(done, 2, "--gui needs an X display")


@pytest.mark.parametrize("args", [("--duration", "3601"), ("--duration", "0"), ("--obstacle", "wall:1001")])
def test_the_other_ranges_in_help_are_the_checked_ones(args: tuple[str, ...]) -> None:
    help_text = " ".join(rdcd("simulate", "--help").stdout.split())
    assert "at most 3600" in help_text and "each at most 1000" in help_text
    assert_clean_failure(rdcd("simulate", PROGRAM, *args), 2, args[0])
