"""Runs of the state examples (examples/gradient.rdcd, count.rdcd, lowest.rdcd, ...) in the
physics-free lattice world: compile with the real front end and compiler, inject every fragment
back to back at the entry module as ``rdcd simulate`` does, run until the links have been quiet
for a while, and read every module's final state by name."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

from rdcd_core.compiler import CompiledProgram, compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config, random_structure
from sim.run import role_table
from sim.sweep.state_checks import hop_distances  # noqa: F401  (the tests' oracle)
from vm.lattice.structure import Structure
from vm.lattice.world import LatticeWorld

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
CONFIGS = ("car7", "car11", "car8-cyclic", "car17-wide", "snake5", "snake12", "snake30")
RANDOM = tuple(f"random{n}-seed{seed}" for seed, n in enumerate(
    (20, 23, 26, 29, 32, 35, 38, 41, 44, 47, 50, 53, 56, 60, 20, 30, 40, 50, 60, 45), start=1))


@functools.cache
def compiled(name: str) -> CompiledProgram:
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    result = check_text(text)
    assert not result.model.has_errors, [d.message for d in result.diagnostics]
    program = compile_model(result.model, text=text)
    assert not program.has_errors, [d.message for d in program.diagnostics]
    return program


def structure(config: str) -> Structure:
    if config.startswith("random"):
        size, seed = config[len("random"):].split("-seed")
        return random_structure(int(size), int(seed))
    return load_config(config)


@dataclass
class StateRun:
    structure: Structure
    world: LatticeWorld
    program: CompiledProgram
    settle_s: float  # the last change of any module's state or role

    def value(self, module: int, name: str) -> int:
        index = next(s.index for s in self.program.states if s.name == name)
        return self.world.runtimes[module].state[index]

    def values(self, name: str) -> dict[int, int]:
        return {m: self.value(m, name) for m in self.structure.ids()}

    def roles(self) -> dict[int, str | None]:
        return self.world.roles_by_name()

    def errors(self) -> dict[int, list[str]]:
        return {m: [e for _, e in r.errors] for m, r in self.world.runtimes.items() if r.errors}

    def packets_per_module(self) -> float:
        return sum(r.link.sent for r in self.world.runtimes.values()) / len(self.world.runtimes)


def run(example: str, config: str, *, seed: int = 0, loss: float = 0.0, limit_s: float = 120.0,
        quiet_s: float = 5.0) -> StateRun:
    program = compiled(example)
    shape = structure(config)
    world = LatticeWorld(shape, role_table(program), seed=seed, packet_loss=loss)
    for name in program.injection:
        world.inject(program.fragment(name).code)
    last_change, last_seen = 0.0, None
    while world.now() < limit_s:
        world.advance(0.1)
        seen = tuple((tuple(r.state), r.role) for r in world.runtimes.values())
        if seen != last_seen:
            last_seen, last_change = seen, world.now()
        elif world.now() - last_change >= quiet_s and world.network.in_flight() == 0:
            break
    return StateRun(shape, world, program, last_change)
