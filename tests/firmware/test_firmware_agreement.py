"""The ``original`` VM profile against the ATRON firmware's own code, module by module.

``firmware_traces.json`` holds what the firmware's interpreter and controller did (README.md beside
this file says how it was recorded) in 60 contexts: the obstacle program and snake_wave, each
compiled for the default and the original target (the exact fragments and role table are in the
file), on car7, car11, car8-cyclic, snake5 and snake8, without an object, with an object in front
of each sensor that has a handler from 45 s on, and with one there for half a second only. Each
context runs here in the lattice world with every module in the profile, the program loaded as the
firmware loads it, and must give the same figures on every module: role, event vectors, command
table, every joint command with its time, every packet on every connector with its time and bytes
(headers included), LEDs, whether it halted and its errors.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

import pytest

from sim.config import load_config
from tests.firmware.traces import Recorder
from vm.isa.targets import ORIGINAL
from vm.lattice.world import LatticeWorld
from vm.roles import RoleTable
from vm.runtime_firmware import FirmwareRuntime

DATA = Path(__file__).with_name("firmware_traces.json")


@cache
def recorded() -> dict[str, Any]:
    return json.loads(DATA.read_text(encoding="utf-8"))


def _id(context: dict[str, Any]) -> str:
    return f"{context['program']}-{context['config']}-{context['scenario']}"


def profile_run(context: dict[str, Any]) -> dict[str, Any]:
    program = recorded()["programs"][context["program"]]
    roles = RoleTable({rid: name for rid, name, _ in program["roles"]},
                      {rid: frozenset(of) for rid, _, of in program["roles"]})
    world = LatticeWorld(load_config(context["config"]), roles, target=ORIGINAL)
    recorder = Recorder(world)
    for fragment in program["fragments"]:
        world.inject(bytes.fromhex(fragment))
    t = 0.0
    for at, cells in context["events"]:
        world.advance(at - t)
        t = at
        world.set_obstacles(frozenset(tuple(c) for c in cells))
    world.advance(context["duration"] - t)
    figures = {}
    for mid, runtime in world.runtimes.items():
        assert isinstance(runtime, FirmwareRuntime)
        figures[str(mid)] = recorder.module(mid, role=runtime.role, vectors=list(runtime.vectors),
                                            table=list(runtime.command_table), halted=runtime.halted,
                                            errors=len(runtime.errors))
    return figures


def test_the_recording_covers_every_context_of_the_issue() -> None:
    contexts = recorded()["contexts"]
    assert len(contexts) == 60
    assert {c["program"] for c in contexts} == {"obstacle/default", "obstacle/original",
                                                "snake_wave/default", "snake_wave/original"}
    assert {c["config"] for c in contexts} == {"car7", "car11", "car8-cyclic", "snake5", "snake8"}
    with_objects = [c for c in contexts if c["events"]]
    assert len(with_objects) == 60 - 20 and all(len(c["events"]) in (1, 2) for c in with_objects)


@pytest.mark.parametrize("context", recorded()["contexts"], ids=_id)
def test_the_profile_does_what_the_firmware_did(context: dict[str, Any]) -> None:
    got = profile_run(context)
    want = context["modules"]
    differences = [f"module {m} {key}: firmware {want[m][key]}, profile {got[m][key]}"
                   for m in want for key in want[m] if got[m][key] != want[m][key]]
    assert differences == []
