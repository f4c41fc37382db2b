"""Issue 11, acceptance 2 in the physics world, and ``rdcd simulate --vm`` end to end: the example
programs in the VM profile ``original`` (the ATRON firmware, docs/vm.md)."""

from __future__ import annotations

import json
import subprocess
import sys
from collections import defaultdict
from functools import cache
from pathlib import Path

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.compiler.program import CompiledProgram
from rdcd_core.frontend import check_text
from server.commands import simulate_arguments
from sim.config import load_config
from sim.run import Options, simulate
from sim.scenario import judge_obstacle
from tests.conftest import EXAMPLES

ROOT = Path(__file__).resolve().parents[2]
SNAKE = EXAMPLES / "snake_wave.rdcd"


@cache
def program(name: str, target: str) -> CompiledProgram:
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    compiled = compile_model(check_text(text).model, text=text, target=target)
    assert compiled.injection and not compiled.has_errors
    return compiled


@cache
def run(name: str, config: str, target: str, duration: float, obstacle: str = "wall:1.0") -> dict:
    options = Options(config=config, obstacle=obstacle, duration=duration, vm="original")
    return simulate(program(name, target), load_config(config), options)


def _failed(checks: dict[str, bool]) -> list[str]:
    return [k for k, ok in checks.items() if not ok]


def test_car7_avoids_a_wall_on_the_firmware() -> None:
    # the entry module loads the 4 fragments 8 s apart before anything drives
    report = run("obstacle_avoidance.rdcd", "car7", "original", 90.0)
    assert (report["vm"], report["target"]) == ("original", "original")
    assert _failed(judge_obstacle(report, load_config("car7"))) == []
    assert not any(m["errors"] for m in report["modules"])


@pytest.mark.slow
def test_car11_reverses_at_a_wall_on_the_firmware_but_does_not_clear_it() -> None:
    """On the firmware SLEEP_ROTATIONS 3 ends when the joint has come back to its starting
    quarter three times (less than three turns), so the car reverses and turns less; car11 meets
    the wall again and again (README, known limits). Every wheel takes Reverse and leaves it."""
    report = run("obstacle_avoidance.rdcd", "car11", "original", 90.0)
    assert not any(m["errors"] for m in report["modules"])
    wheels = [m for m in report["modules"] if m["role_history"] and "Wheel" in m["role_history"][0][1]]
    assert len(wheels) == 6
    for m in wheels:
        names = [r for _, r in m["role_history"]]
        assert names[0] in ("LeftWheel", "RightWheel") and f"Reverse@{names[0]}" in names
        assert names.count(names[0]) >= 2  # back to its base role after reversing
    assert "no_reverse_left" in _failed(judge_obstacle(report, load_config("car11")))


def _joint_commands(report: dict) -> dict[int, list[tuple[int, int]]]:
    out: dict[int, list[tuple[int, int]]] = defaultdict(list)
    for event in report["events"]:
        if event["kind"] == "command" and event["detail"]["command"] == 5:  # ROTATE_TO
            out[event["module"]].append(event["detail"]["arg"])
    return out


def test_snake_wave_finds_head_and_body_and_waves_on_the_firmware() -> None:
    report = run("snake_wave.rdcd", "snake5", "original", 45.0, obstacle="none")
    roles = {m["id"]: m["final_role"] for m in report["modules"]}
    assert roles == {0: None, 1: "Body", 2: "Body", 3: "Body", 4: "Head"}
    assert not any(m["errors"] for m in report["modules"])
    commands = _joint_commands(report)
    for mid, role in roles.items():
        if role is None:
            assert mid not in commands
            continue
        swing = 4 if role == "Head" else 2  # turnTowards(40) and (20): ROTATE_TO in tens of degrees
        assert len(commands[mid]) >= 8 and set(commands[mid]) == {swing, -swing}, (mid, commands[mid])
        assert all(a == -b for a, b in zip(commands[mid], commands[mid][1:], strict=False))  # to and fro


def test_car8_cyclic_programs_circulate_on_the_firmware() -> None:
    """Fragments go round the cycle and run again on each lap until stores or task queues of
    modules on the cycle overflow; the firmware stops such a module for good."""
    report = run("obstacle_avoidance.rdcd", "car8-cyclic", "original", 60.0)
    halted = [e["message"] for m in report["modules"] for e in m["errors"] if e["message"].endswith("halted")]
    assert halted and all("task queue full" in m or "program store full" in m for m in halted)
    assert not report["modules"][0]["errors"]  # the entry module loads, then forwards little
    default = simulate(program("obstacle_avoidance.rdcd", "original"), load_config("car8-cyclic"),
                       Options(config="car8-cyclic", duration=60.0))
    assert not any(m["errors"] for m in default["modules"])


def _cli(tmp_path: Path, *args: str) -> tuple[subprocess.CompletedProcess[str], dict | None]:
    out = tmp_path / f"report{len(list(tmp_path.iterdir()))}.json"
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "simulate", *args, "--report", str(out)],
                          capture_output=True, text=True, cwd=ROOT, timeout=300, check=False)
    return done, json.loads(out.read_text(encoding="utf-8")) if out.exists() else None


def test_cli_shows_the_equals_2_halt_of_default_code_on_the_firmware(tmp_path: Path) -> None:
    # the entry module sends the discovery fragment at 8 s (dcd_action); its neighbour halts on it
    done, report = _cli(tmp_path, str(SNAKE), "--config", "snake5", "--world", "physics",
                        "--duration", "9", "--vm", "original", "--target", "default")
    assert done.returncode == 0, done.stderr
    assert "(original VM, program compiled for the default target)" in done.stdout
    assert ("module 1, fragment discover_Head_Body, pc 24, line 30: unknown instruction 8 (EQUALS_2); "
            "module halted") in done.stdout  # line 30 of snake_wave.rdcd: the invariant that compiled to it
    assert report is not None and (report["vm"], report["target"]) == ("original", "default")
    assert not report["modules"][0]["errors"]
    (error,) = report["modules"][1]["errors"]
    assert (error["fragment"], error["pc"]) == ("discover_Head_Body", 24)
    assert all(m["final_role"] is None for m in report["modules"])


def test_cli_vm_defaults_and_refuses_unknown_profiles(tmp_path: Path) -> None:
    done, report = _cli(tmp_path, str(SNAKE), "--config", "snake5", "--world", "lattice", "--duration", "5")
    assert done.returncode == 0, done.stderr
    assert report is not None and (report["vm"], report["target"]) == ("default", "default")
    assert done.stdout.splitlines()[0] == "snake5 in the lattice world, obstacle wall:1.0, 5 s, seed 0"
    done, report = _cli(tmp_path, str(SNAKE), "--world", "lattice", "--vm", "firmware")
    assert done.returncode == 2 and "--vm" in done.stderr and report is None


def test_the_server_passes_the_vm_profile_on() -> None:
    options = {"world": "lattice", "vm": "original", "target": "default"}
    argv = simulate_arguments(Path("p.rdcd"), options, Path("r.json"), Path("p.png"), Path("r.html"))
    assert "--vm=original" in argv and "--target=default" in argv  # --flag=value: no value is a flag
    plain = simulate_arguments(Path("p.rdcd"), {}, Path("r.json"), Path("p.png"), Path("r.html"))
    assert not any(a.startswith("--vm") for a in plain)


def test_simulate_refuses_an_unknown_profile() -> None:
    with pytest.raises(ValueError, match="unknown VM profile 'firmware'"):
        simulate(program("snake_wave.rdcd", "default"), load_config("snake5"),
                 Options(world="lattice", duration=1.0, vm="firmware"))
