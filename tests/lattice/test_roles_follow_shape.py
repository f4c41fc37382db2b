"""Roles follow the shape (issue 23, item 3; docs/language.md "Invariants and discovery order",
docs/vm.md "When discovery runs"): a module takes the first deployed role whose invariants hold —
on program arrival, after a value change, after a connection change — in the default VM and for
code compiled for the firmware. Expected roles are computed here from the true structure."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm import navigation as nav
from vm.isa.targets import TARGETS
from vm.lattice.structure import Structure
from vm.lattice.world import LatticeWorld

sys.path.insert(0, str(Path(__file__).resolve().parent))
from links import set_link, unlink  # noqa: E402 - the helper next to this file

WHEEL = "self.center_position == EAST_WEST; sizeof(self.total_connected()) == 1;"
STATELESS = f"role Wheel {{ {WHEEL} }}\nrole Other {{ }}\ndeployment {{ Wheel, Other }}\n"
STATEFUL = (f"state s := 0;\nrole Wheel {{ {WHEEL} s == 0; }}\nrole Other {{ }}\n"
            "deployment { Wheel, Other }\n")
CARS = {"car7": {"Wheel": 4, "Other": 3}, "car11": {"Wheel": 6, "Other": 5}}


def compiled(text: str, target: str = "default"):
    checked = check_text(text)
    assert not checked.has_errors, checked.diagnostics
    return compile_model(checked.model, text=text, target=target)


def world_with(text: str, config: str | Structure, *, target: str = "default", vm: str = "default",
               detached: tuple[int, ...] = (), seed: int = 0, loss: float = 0.0):
    """A world running ``text``; ``detached`` modules are cut off before the injection."""
    program = compiled(text, target)
    assert not program.has_errors, program.diagnostics
    structure = load_config(config) if isinstance(config, str) else config
    world = LatticeWorld(structure, role_table(program), target=TARGETS[vm], seed=seed, packet_loss=loss)
    cut = [link for module in detached for link in unlink(world, module)]
    for name in program.injection:
        world.inject(program.fragment(name).code)
    world.advance(20.0 if vm == "default" else 8.0 * len(program.injection) + 20.0)
    return world, cut


def connections(world: LatticeWorld, module: int) -> tuple[int, int]:
    """(true axis, virtual connected set) of a module, from the world's links and its mount."""
    spec = world.structure.modules[module]
    p2v = nav.invert(spec.mount.physical_map())
    virtual = sum(1 << p2v[ch] for ch in world.hals[module].connected_channels())
    return spec.axis, virtual


def wheel_or_other(world: LatticeWorld, module: int) -> str:
    axis, virtual = connections(world, module)
    return "Wheel" if axis == nav.EAST_WEST and virtual.bit_count() == 1 else "Other"


def expected(world: LatticeWorld) -> dict[int, str]:
    return {mid: wheel_or_other(world, mid) for mid in world.runtimes}


@pytest.mark.parametrize("config", sorted(CARS))
@pytest.mark.parametrize("text", [STATELESS, STATEFUL], ids=["stateless", "stateful"])
def test_the_first_holding_role_wins_in_the_default_vm(config: str, text: str) -> None:
    world, _ = world_with(text, config)
    assert Counter(world.roles_by_name().values()) == CARS[config]
    assert world.roles_by_name() == expected(world)


@pytest.mark.parametrize("config", sorted(CARS))
def test_code_for_the_firmware_lets_the_first_role_win(config: str) -> None:
    """Compiled for --target original: in the default VM as there, and on the firmware profile,
    where the entry module loads the fragments (dcd_action) and runs none of them."""
    world, _ = world_with(STATELESS, config, target="original")
    assert Counter(world.roles_by_name().values()) == CARS[config]
    world, _ = world_with(STATELESS, config, target="original", vm="original")
    roles = world.roles_by_name()
    entry = world.structure.entry
    assert roles[entry] is None
    assert {mid: role for mid, role in roles.items() if mid != entry} == \
        {mid: role for mid, role in expected(world).items() if mid != entry}


def test_state_dependent_roles_cannot_be_compiled_for_the_firmware() -> None:
    program = compile_model(check_text(STATEFUL).model, text=STATEFUL, target="original")
    assert "E605" in {d.code for d in program.diagnostics}


@pytest.mark.parametrize("text", [STATELESS, STATEFUL], ids=["stateless", "stateful"])
def test_a_detached_wheel_checks_its_roles_again(text: str) -> None:
    world, _ = world_with(text, "car7")
    wheel = next(mid for mid, role in world.roles_by_name().items() if role == "Wheel")
    cut = unlink(world, wheel)
    world.advance(5.0)
    assert world.roles_by_name()[wheel] == "Other"  # alone: no connection, Other holds
    assert world.roles_by_name() == expected(world)
    for link in cut:
        set_link(world, link, True)
    world.advance(5.0)
    assert Counter(world.roles_by_name().values()) == CARS["car7"]
    assert all(state.frame_correct for state in world.states())
    assert world.runtimes[wheel].errors == []


@pytest.mark.parametrize("text", [STATELESS, STATEFUL], ids=["stateless", "stateful"])
def test_a_module_that_loses_a_neighbour_takes_the_role_its_shape_gives(text: str) -> None:
    """Cutting every link of car11 once: the modules on both sides, and every other module, end
    with the first role that holds in the new shape (a module left with one connection on the
    east-west axis becomes a Wheel)."""
    world, _ = world_with(text, "car11")
    for link in [(a, pa, b, pb) for a, ports in world.network._ports.items()  # noqa: SLF001
                 for pa, (b, pb) in sorted(ports.items()) if a < b]:
        set_link(world, link, False)
        world.advance(4.0)
        assert world.roles_by_name() == expected(world), link
        set_link(world, link, True)
        world.advance(4.0)
        assert Counter(world.roles_by_name().values()) == CARS["car11"], link


NEAR = " + ".join(f"sizeof(connected_role({d}, Wheel))" for d in ("UP", "DOWN", "EAST", "WEST",
                                                                   "NORTH", "SOUTH"))
OBSERVING = f"role Wheel {{ {WHEEL} }}\nrole Near {{ {NEAR} > 0; }}\nrole Other {{ }}\n" \
    "deployment { Wheel, Near, Other }\n"


def test_a_neighbours_new_role_is_heard_and_checked() -> None:
    """A module whose own connections do not change, but whose neighbour becomes a Wheel (or stops
    being one) when that neighbour loses a link, checks its roles again (connected_role)."""
    world, _ = world_with(OBSERVING, "car11")

    def want() -> dict[int, str]:
        simple = expected(world)
        ports = world.network._ports  # noqa: SLF001
        return {mid: role if role == "Wheel" else
                "Near" if any(simple[b] == "Wheel" for b, _ in ports[mid].values()) else "Other"
                for mid, role in simple.items()}

    assert world.roles_by_name() == want()
    for link in [(a, pa, b, pb) for a, ports in world.network._ports.items()  # noqa: SLF001
                 for pa, (b, pb) in sorted(ports.items()) if a < b]:
        set_link(world, link, False)
        world.advance(6.0)
        assert world.roles_by_name() == want(), link
        set_link(world, link, True)
        world.advance(6.0)
        assert world.roles_by_name() == want(), link


@pytest.mark.parametrize("text", [STATELESS, STATEFUL], ids=["stateless", "stateful"])
@pytest.mark.parametrize("loss", [0.0, 0.2])
def test_a_module_attached_later_receives_the_programs_and_takes_its_role(text: str, loss: float) -> None:
    world, cut = world_with(text, "car11", detached=(5,), loss=loss, seed=3)
    assert world.runtimes[5].programs_run == 0 and world.roles_by_name()[5] is None
    for link in cut:
        set_link(world, link, True)
    world.advance(25.0)
    assert world.runtimes[5].programs_run > 0
    assert world.roles_by_name() == expected(world)
    assert world.state(5).frame_correct
    neighbour, _ = next(iter(world.network._ports[5].values()))  # noqa: SLF001
    role = world.runtimes[5].role
    assert role in world.runtimes[neighbour].neighbour_roles  # it heard of the new role


def test_the_firmware_profile_never_looks_at_its_connections_again() -> None:
    world, _ = world_with(STATELESS, "car7", target="original", vm="original")
    before = world.roles_by_name()
    wheel = next(mid for mid, role in before.items() if role == "Wheel")
    unlink(world, wheel)
    world.advance(5.0)
    assert world.roles_by_name() == before


# ---- property: random roles, deployments and structures ----------------------------------------

AXES = {"EAST_WEST": nav.EAST_WEST, "NORTH_SOUTH": nav.NORTH_SOUTH, "UP_DOWN": nav.UP_DOWN}
DIRS = {"EAST": nav.EAST, "WEST": nav.WEST, "NORTH": nav.NORTH, "SOUTH": nav.SOUTH,
        "UP": nav.UP, "DOWN": nav.DOWN}
OPS = {"==": int.__eq__, "!=": int.__ne__, "<": int.__lt__, ">": int.__gt__}

atom = st.one_of(
    st.tuples(st.just("axis"), st.sampled_from(sorted(AXES)), st.booleans()),
    st.tuples(st.just("total"), st.sampled_from(sorted(OPS)), st.integers(0, 3)),
    st.tuples(st.just("dir"), st.sampled_from(sorted(DIRS)), st.sampled_from(sorted(OPS)), st.integers(0, 2)),
)


def source(atom_: tuple) -> str:
    if atom_[0] == "axis":
        return f"self.center_position {'==' if atom_[2] else '!='} {atom_[1]}"
    if atom_[0] == "total":
        return f"sizeof(self.total_connected()) {atom_[1]} {atom_[2]}"
    return f"sizeof(self.connected({atom_[1]})) {atom_[2]} {atom_[3]}"


def holds(atom_: tuple, axis: int, virtual: int) -> bool:
    if atom_[0] == "axis":
        return (axis == AXES[atom_[1]]) == atom_[2]
    if atom_[0] == "total":
        return OPS[atom_[1]](virtual.bit_count(), atom_[2])
    count = (virtual & nav.channels_facing(axis, DIRS[atom_[1]])).bit_count()
    return OPS[atom_[2]](count, atom_[3])


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(roles=st.lists(st.lists(atom, max_size=2), min_size=1, max_size=4),
       order=st.randoms(use_true_random=False),
       config=st.sampled_from(["car7", "car11", "snake5", "random12-seed4", "random20-seed7"]),
       state=st.booleans(), cut=st.integers(0, 30))
def test_final_role_is_the_first_deployed_role_that_holds(roles, order, config, state, cut) -> None:
    names = [f"R{i}" for i in range(len(roles))]
    deployment = list(names)
    order.shuffle(deployment)
    lines = ["state s := 0;"] if state else []
    for name, invariants in zip(names, roles, strict=True):
        body = [source(a) + ";" for a in invariants] + (["s == 0;"] if state else [])
        lines.append(f"role {name} {{ {' '.join(body)} }}")
    text = "\n".join(lines) + f"\ndeployment {{ {', '.join(deployment)} }}\n"
    checked = check_text(text)
    if checked.has_errors:
        return
    program = compiled(text)
    if program.max_fragment_bytes > program.program_budget:
        return  # over the IR packet limit (W601): the robot would never receive it, nor do the worlds
    world, _ = world_with(text, config)

    def first_holding() -> dict[int, str | None]:
        out: dict[int, str | None] = {}
        for mid in world.runtimes:
            axis, virtual = connections(world, mid)
            out[mid] = next((name for name in deployment
                             if all(holds(a, axis, virtual) for a in roles[names.index(name)])), None)
        return out

    assert world.roles_by_name() == first_holding(), text
    links = [(a, pa, b, pb) for a, ports in world.network._ports.items()  # noqa: SLF001
             for pa, (b, pb) in sorted(ports.items()) if a < b]
    link = links[cut % len(links)]
    set_link(world, link, False)
    world.advance(5.0)
    assert world.roles_by_name() == first_holding(), (text, link)
