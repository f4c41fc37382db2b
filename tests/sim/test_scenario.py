"""The obstacle program on simulated cars (spec/atron.md). One short physics run in CI; the
other configurations are slow and run only with RDCD_SLOW=1 (benchmarks/scenarios.py has them
all, with packet-loss runs)."""

from __future__ import annotations

import os

import pytest

from sim.config import load_config
from sim.run import Options, simulate
from sim.scenario import judge_obstacle, judge_straight, reverse_spans
from tests.sim.helpers import obstacle_program

slow = pytest.mark.skipif(not os.environ.get("RDCD_SLOW"), reason="slow physics scenario: set RDCD_SLOW=1")


def _run(config: str, obstacle: str, duration: float, **kw: object) -> dict:
    options = Options(config=config, obstacle=obstacle, duration=duration, **kw)  # type: ignore[arg-type]
    return simulate(obstacle_program(), load_config(config), options)


def _assert_all(checks: dict[str, bool]) -> None:
    assert all(checks.values()), [k for k, ok in checks.items() if not ok]


def test_car7_avoids_a_wall() -> None:
    report = _run("car7", "wall:1.0", 60.0)
    _assert_all(judge_obstacle(report, load_config("car7")))
    assert report["min_obstacle_distance_m"] > 0.02
    assert len(report["trajectory"]) >= 10 * 60
    assert reverse_spans(report)[0][1] is not None
    again = _run("car7", "wall:1.0", 60.0)
    assert again["trajectory"] == report["trajectory"]  # deterministic


@slow
@pytest.mark.slow
@pytest.mark.parametrize("config", ["car11", "car8-cyclic", "car17-wide"])
def test_other_cars_avoid_a_wall(config: str) -> None:
    _assert_all(judge_obstacle(_run(config, "wall:1.0", 60.0), load_config(config)))


@slow
@pytest.mark.slow
def test_car7_drives_straight_without_obstacle() -> None:
    _assert_all(judge_straight(_run("car7", "none", 20.0), load_config("car7")))


@slow
@pytest.mark.slow
def test_car7_with_packet_loss() -> None:
    _assert_all(judge_obstacle(_run("car7", "wall:1.0", 60.0, seed=5, packet_loss=0.1), load_config("car7")))
