"""Issue 11, acceptance 2 in the lattice world: the example programs in the VM profile ``original``
(the ATRON firmware as docs/firmware.md describes it), compiled for the original target and, to show
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


def _snake(target: str, vm, seconds: float = 50.0) -> tuple[LatticeWorld, dict[int, list[float]]]:  # noqa: ANN001
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
    firmware does not implement. The entry module only sends it (dcd_action, at 8 s); its
    neighbour runs it and halts, so nothing spreads further or waves."""
    world, angles = _snake("default", ORIGINAL, seconds=30.0)
    entry = world.runtimes[world.structure.entry]
    assert not entry.halted and entry.programs_run == 0
    (first,) = [m for m, r in world.runtimes.items() if r.halted]
    halted = world.runtimes[first]
    (error,) = halted.run_errors
    assert error.message.endswith("pc 24: unknown instruction 8 (EQUALS_2); module halted")
    assert error.message.endswith("module halted") and 8.0 <= error.t < 8.1
    program = compiled("default", SNAKE)
    discovery = program.fragment("discover_Head_Body").code
    assert error.code == discovery and discovery[error.pc] == 8
    assert all(r.role == 0 and r.programs_run == 0 for m, r in world.runtimes.items() if m not in (first,))
    assert all(a == 0.0 for values in angles.values() for a in values)
    # the same code waves in this project's VM
    default_world, default_angles = _snake("default", DEFAULT, seconds=10.0)
    assert "Head" in default_world.roles_by_name().values()


def test_car8_cyclic_on_the_firmware_fills_stores_and_queues_on_the_cycle() -> None:
    """No duplicate suppression: the fragments go round the cycle driver – rear axle – bridge and
    run again on each lap, until program stores and task queues of modules on the cycle overflow
    and those modules stop (the firmware's report_error never returns). The entry module loads
    the fragments first (8 s each) and forwards little."""
    structure_name = "car8-cyclic"
    run = start(structure_name, target="original", vm=ORIGINAL, limit_s=40.0, margin_s=0.0)
    world = run.world
    world.advance(120.0 - world.now())
    counts = run.run_counts()
    assert any(n > 1 for c in counts.values() for n in c.values())  # fragments ran again and again
    halted = {m: r.errors[0][1] for m, r in world.runtimes.items() if r.halted}
    assert sorted(halted) == [2, 3, 4]
    assert "task queue full" in halted[2] and all("program store full" in halted[m] for m in (3, 4))
    entry = world.runtimes[world.structure.entry]
    assert entry.stats()["sent"] == 60 and not entry.errors
    default = start(structure_name, target="original", vm=DEFAULT)
    assert default.problems() == []


def _head_sees(vm, at: float, seconds: float) -> tuple[int, list[float]]:  # noqa: ANN001
    """snake_wave (original target) with an obstacle cell in front of the Head's sensor 0 from
    ``at`` for ``seconds``: (detections logged by the Head, times its handler ran)."""
    world, _ = _snake("original", vm, seconds=at)
    structure = world.structure
    head = max(structure.modules, key=lambda m: structure.modules[m].position[1])
    (x, y, z), (dx, dy, dz) = structure.modules[head].position, structure.physical_direction(head, 0)
    since = len(world.events)
    world.set_obstacles(frozenset({(x + dx, y + dy, z + dz)}))
    world.advance(seconds)
    world.set_obstacles(frozenset())
    world.advance(1.0)
    events = world.events[since:]
    detections = [t for t, m, kind, _ in events if kind == "handler" and m == head]
    return len(detections) + world.runtimes[head].stats()["handler_refires"], detections


def test_an_object_seen_while_the_head_sleeps_is_missed_on_the_firmware() -> None:
    """The firmware looks at its sensors between tasks only, and the Head's behaviour sleeps a
    second at a time (SLEEP blocks the module): half a second of an object in between is never
    noticed. This project's VM notices it."""
    runs, _ = _head_sees(ORIGINAL, 45.3, 0.5)
    assert runs == 0
    runs, _ = _head_sees(DEFAULT, 45.3, 0.5)
    assert runs == 1


def test_a_handler_runs_at_most_once_a_second_while_its_module_sleeps_in_a_loop() -> None:
    """snake_wave's Head handler does not disable its event (the compiler warns, W604); on the
    firmware it could run on every scheduler step while the sensor sees, but the Head is blocked
    in SLEEP for all but one step a second: two seconds of an object, one or two runs."""
    runs, times = _head_sees(ORIGINAL, 45.0, 2.0)
    assert 1 <= runs <= 2 and len(times) == 1
