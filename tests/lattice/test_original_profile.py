"""Issue 11, acceptance 2 in the lattice world: the example programs in the VM profile ``original``
(the ATRON firmware as docs/vm.md describes it), compiled for the original target and, to show
what a user meets on the robot, for the default target."""

from __future__ import annotations

import pytest

from tests.conftest import EXAMPLES
from tests.integration.lattice_harness import compiled, reverse_scenario, start
from vm import navigation as nav
from vm.isa.targets import DEFAULT, ORIGINAL
from vm.lattice.structure import Structure
from vm.lattice.world import LatticeWorld

SNAKE = EXAMPLES / "snake_wave.rdcd"


def firmware_x_errors(structure: Structure) -> dict[int, tuple[int, int, int]]:
    """Where each module wrongly believes it is on the firmware: its position computed along the
    diffusion tree from the entry with the UD 5/7 x-offsets swapped, where that differs."""
    at = {spec.position: mid for mid, spec in structure.modules.items()}
    learned = {structure.entry: (0, 0, 0)}
    todo = [structure.entry]
    while todo:
        mid = todo.pop(0)
        spec = structure.modules[mid]
        for v in nav.CHANNELS:
            other = at.get(nav.receiver(*spec.position, spec.axis, v)[:3])
            if other is not None and other not in learned:
                learned[other] = nav.receiver(*learned[mid], spec.axis, v, ud_offsets_swapped=True)[:3]
                todo.append(other)
    return {m: p for m, p in learned.items() if p != structure.modules[m].position}


def without_wrong_x(problems: list[str]) -> list[str]:
    return [p for p in problems if "learned" not in p]


@pytest.mark.parametrize("config", ["car7", "car11"])
def test_obstacle_program_for_the_original_target_finds_its_roles_and_reverses(config: str) -> None:
    run = start(config, target="original", vm=ORIGINAL)
    assert without_wrong_x(run.problems()) == []
    assert run.roles() == run.structure.expected_roles
    # the wheels hang on the axles' UD channels 5 and 7: on the firmware they learn a mirrored x,
    # which this program never reads
    wrong = firmware_x_errors(run.structure)
    assert wrong and {m: s.position for m, s in ((s.id, s) for s in run.world.states())
                      if s.position != s.true_position} == wrong
    result = reverse_scenario(run)
    assert without_wrong_x(result.problems) == []
    assert result.handlers == [result.detector]


def test_obstacle_program_for_the_default_target_also_runs_on_the_firmware_of_a_tree() -> None:
    """What the issue measured in the authors' interpreter: every opcode it uses exists there."""
    run = start("car7", target="default", vm=ORIGINAL)
    assert without_wrong_x(run.problems()) == []
    assert without_wrong_x(reverse_scenario(run).problems) == []


def _snake(target: str, vm, seconds: float = 20.0) -> tuple[LatticeWorld, dict[int, list[float]]]:  # noqa: ANN001
    from sim.config import load_config
    from sim.run import role_table

    program = compiled(target, SNAKE)
    structure = load_config("snake5")
    world = LatticeWorld(structure, role_table(program), target=vm)
    for name in program.injection:
        world.inject(program.fragment(name).code)
    angles: dict[int, list[float]] = {mid: [] for mid in structure.modules}
    for _ in range(int(seconds / 0.25)):
        world.advance(0.25)
        for mid, hal in world.hals.items():
            angles[mid].append(hal.joint_angle_deg())
    return world, angles


def test_snake_wave_for_the_original_target_finds_head_and_body_and_waves() -> None:
    world, angles = _snake("original", ORIGINAL)
    roles = world.roles_by_name()
    structure = world.structure
    tail = max(structure.modules, key=lambda m: structure.modules[m].position[1])
    assert roles[tail] == "Head"
    assert sorted(r for m, r in roles.items() if r is not None and m != tail) == ["Body"] * 3
    assert roles[structure.entry] is None  # one connection at y = 0: neither Head nor Body
    assert not any(r.errors for r in world.runtimes.values())
    for mid, role in roles.items():
        late = angles[mid][len(angles[mid]) // 2:]
        if role is None:
            assert set(late) == {0.0}
            continue
        # turnTowards(±swing) a second apart: Body reaches ±20°; Head turns back before ±40°
        assert max(late) > 15.0 and min(late) < -15.0, (mid, role)
        assert sum(1 for a, b in zip(late, late[1:], strict=False) if a * b < 0) >= 4  # to and fro


def test_snake_wave_for_the_default_target_halts_on_the_firmware_at_equals_2() -> None:
    """The failure the issue met on the robot: the discovery fragment uses EQUALS_2, which the
    firmware does not implement; the entry module halts and nothing spreads or waves."""
    world, angles = _snake("default", ORIGINAL, seconds=10.0)
    entry = world.runtimes[world.structure.entry]
    assert entry.halted
    (error,) = entry.run_errors
    assert error.message.endswith("unknown instruction 8 (EQUALS_2); module halted")
    program = compiled("default", SNAKE)
    discovery = program.fragment("discover_Head_Body").code
    assert error.code == discovery and discovery[error.pc] == 8
    assert all(r.role == 0 and r.programs_run == 0 for m, r in world.runtimes.items() if m != entry.module_id)
    assert all(a == 0.0 for values in angles.values() for a in values)
    # the same code waves in this project's VM
    default_world, default_angles = _snake("default", DEFAULT, seconds=10.0)
    assert "Head" in default_world.roles_by_name().values()


def test_car8_cyclic_shows_the_circulation_failure_on_the_firmware() -> None:
    """No duplicate suppression: every fragment goes round the cycle driver – rear axle – bridge
    for ever, each lap runs it again on every module of the cycle, and the stores and queues of
    the modules on the cycle overflow (docs/vm.md)."""
    structure_name = "car8-cyclic"
    run = start(structure_name, target="original", vm=ORIGINAL, limit_s=8.0, margin_s=0.0)
    runtimes = run.world.runtimes
    counts = run.run_counts()
    assert any(n > 1 for c in counts.values() for n in c.values())  # fragments ran again and again
    messages = [m for r in runtimes.values() for _, m in r.errors]
    assert any("not accepted" in m and ("task queue full" in m or "program slots are in use" in m)
               for m in messages)
    before = run.world.counters.sent
    run.world.advance(2.0)
    assert run.world.counters.sent - before > 100  # still circulating
    default = start(structure_name, target="original", vm=DEFAULT)
    assert default.problems() == []


def _flashes_with_an_obstacle_at_the_head(vm) -> tuple[int, int]:  # noqa: ANN001
    """snake_wave (original target) with an obstacle cell in front of the Head's sensor 0 for
    2 s: (handler detections logged, flash commands run on the Body modules)."""
    world, _ = _snake("original", vm, seconds=6.0)
    structure = world.structure
    head = max(structure.modules, key=lambda m: structure.modules[m].position[1])
    (x, y, z), (dx, dy, dz) = structure.modules[head].position, structure.physical_direction(head, 0)
    since = len(world.events)
    world.set_obstacles(frozenset({(x + dx, y + dy, z + dz)}))
    world.advance(2.0)
    world.set_obstacles(frozenset())
    world.advance(1.0)
    events = world.events[since:]
    detections = sum(1 for _, m, kind, _ in events if kind == "handler" and m == head)
    flashes = sum(1 for _, m, kind, d in events if kind == "command" and d["command"] == 128 and m != head)
    assert world.runtimes[head].stats()["handler_refires"] == flashes // 3 - 1  # runs after the first
    return detections, flashes


def test_a_handler_that_keeps_its_event_enabled_re_fires_on_the_firmware() -> None:
    """snake_wave's Head handler does not disable its event (the compiler warns, W604): on the
    firmware it runs on every scheduler step while the sensor sees, flooding flash commands."""
    detections, flashes = _flashes_with_an_obstacle_at_the_head(ORIGINAL)
    assert detections == 1 and flashes > 3 * 20  # 3 Body modules, about every step for 2 s
    detections, flashes = _flashes_with_an_obstacle_at_the_head(DEFAULT)
    assert (detections, flashes) == (1, 3)  # once per detection in this project's VM
