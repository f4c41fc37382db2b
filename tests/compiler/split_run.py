"""Runs a program split into fragments that fit, and its unsplit form, in the lattice world: the
unsplit form is compiled for one program slot per fragment (64 bytes) and runs in a world whose
links carry packets of any size (the IR limit lifted), so both run the same source."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import vm.lattice.network as network
from rdcd_core.compiler import CompiledProgram, compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm.lattice.structure import directions
from vm.lattice.world import LatticeWorld

UNSPLIT_PACKET = 7 + 64  # header + a whole program slot: nothing up to 64 bytes is split


@contextmanager
def no_packet_limit() -> Iterator[None]:
    saved = network.PACKET_BUDGET
    network.PACKET_BUDGET = 10_000
    try:
        yield
    finally:
        network.PACKET_BUDGET = saved


def both(text: str) -> tuple[CompiledProgram, CompiledProgram]:
    """(split, unsplit) compilations of ``text``."""
    result = check_text(text)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    split = compile_model(result.model, text=text)
    unsplit = compile_model(result.model, text=text, packet_budget=UNSPLIT_PACKET)
    return split, unsplit


def run(program: CompiledProgram, config: str = "car7", loss: float = 0.0, seconds: float = 10.0,
        seed: int = 5, obstacles: bool = False) -> LatticeWorld:
    """``obstacles``: every free cell a connector of a module faces holds an obstacle (every
    proximity sensor sees one: the handlers fire)."""
    structure = load_config(config)
    world = LatticeWorld(structure, role_table(program), seed=seed, packet_loss=loss)
    if obstacles:
        taken = {spec.position for spec in structure.modules.values()}
        world.set_obstacles(frozenset(
            cell for spec in structure.modules.values() for d in directions(spec)
            if (cell := tuple(p + q for p, q in zip(spec.position, d, strict=True))) not in taken))
    for name in program.injection:  # back to back, as rdcd simulate does
        world.inject(program.fragment(name).code)
    world.advance(seconds)
    return world


def outcome(program: CompiledProgram, world: LatticeWorld) -> dict[int, tuple]:
    """Per module: its role, its state values by name (a role state only where its role is played:
    elsewhere it is no value of the program), its LED, its joint's angle, its runtime errors."""
    found = {}
    roles = world.roles_by_name()
    for mid, runtime in sorted(world.runtimes.items()):
        states = tuple((s.name, runtime.state[s.index]) for s in program.states
                       if s.owner is None or roles.get(mid) in s.roles)
        found[mid] = (roles.get(mid), states, runtime.led, round(world.hals[mid].joint_angle_deg()),
                      tuple(message for _, message in runtime.errors))
    return found


def same_outcome(text: str, config: str = "car7", loss: float = 0.0, seconds: float = 10.0,
                 seed: int = 5, obstacles: bool = False) -> tuple[dict, dict]:
    """The outcomes of the split program (IR limit enforced) and of its unsplit form (no limit)."""
    split, unsplit = both(text)
    with no_packet_limit():
        before = outcome(unsplit, run(unsplit, config, loss, seconds, seed, obstacles))
    after = outcome(split, run(split, config, loss, seconds, seed, obstacles))
    return after, before
