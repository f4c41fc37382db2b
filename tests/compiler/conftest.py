"""Helpers for the compiler tests: check a program's text and compile it."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from rdcd_core.compiler import CompiledProgram, compile_model
from rdcd_core.frontend import CheckResult, check_text

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
# examples that use state or change the structure: they need the default target's extension
# instructions (tests/state, tests/lattice/test_changing_world.py)
STATE_EXAMPLES = frozenset({"gradient.rdcd", "count.rdcd", "lowest.rdcd", "hops.rdcd", "obstacle_memory.rdcd",
                            "snake_gait.rdcd", "grow.rdcd", "move_one.rdcd", "eight_to_snake.rdcd",
                            "car_to_snake.rdcd", "eight_to_car.rdcd"})


def firmware_examples() -> list[Path]:
    """The examples written for both targets (not the verbatim figure, not the state examples)."""
    return [path for path in sorted(EXAMPLES.glob("*.rdcd"))
            if "verbatim" not in path.name and path.name not in STATE_EXAMPLES]


def _check(text: str) -> CheckResult:
    result = check_text(text)
    assert not result.has_errors, [(d.code, d.message) for d in result.diagnostics]
    return result


def _compile(text: str, **options: object) -> CompiledProgram:
    return compile_model(_check(text).model, text=text, **options)  # type: ignore[arg-type]


@pytest.fixture
def check() -> Callable[[str], CheckResult]:
    return _check


@pytest.fixture
def compile_text() -> Callable[..., CompiledProgram]:
    return _compile


@pytest.fixture(scope="session")
def obstacle_text() -> str:
    return (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def obstacle(obstacle_text: str) -> CompiledProgram:
    return _compile(obstacle_text)


@pytest.fixture(scope="session")
def example_programs() -> dict[str, CompiledProgram]:
    return {path.name: _compile(path.read_text(encoding="utf-8")) for path in firmware_examples()}
