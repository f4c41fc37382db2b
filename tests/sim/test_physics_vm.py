"""The physics world with real module runtimes: learned frames, IR links, sensors, joints."""

from __future__ import annotations

import pytest

from sim.config import load_config, random_structure
from sim.obstacles import parse_obstacle
from sim.world import PhysicsWorld
from tests.sim.helpers import MIGRATE_CONTINUE
from vm.roles import RoleTable


def _learned_frames_match(structure, loss: float = 0.0, seconds: float = 2.0) -> list[int]:  # noqa: ANN001
    world = PhysicsWorld(structure, packet_loss=loss, seed=3)
    try:
        runtimes = world.add_runtimes(RoleTable(), seed=3)
        runtimes[structure.entry].inject(MIGRATE_CONTINUE)
        world.advance(seconds)
        return [mid for mid, spec in structure.modules.items()
                if (runtimes[mid].position, runtimes[mid].axis, runtimes[mid].mapping)
                != (spec.position, spec.axis, spec.mount.physical_map())]
    finally:
        world.close()


@pytest.mark.parametrize("name", ["car7", "car11", "car8-cyclic", "car17-wide"])
def test_shipped_configs_learn_their_true_frames(name: str) -> None:
    assert _learned_frames_match(load_config(name)) == []


# 20 random structures of 5..43 modules (acceptance: "for 20 random structures").
RANDOM_STRUCTURES = [(5 + 2 * i, 100 + i) for i in range(20)]


@pytest.mark.parametrize("n,seed", RANDOM_STRUCTURES)
def test_random_structures_learn_their_true_frames(n: int, seed: int) -> None:
    assert _learned_frames_match(random_structure(n, seed)) == []


def test_frames_learned_despite_packet_loss() -> None:
    assert _learned_frames_match(load_config("car11"), loss=0.1, seconds=4.0) == []


class _Inbox:
    def __init__(self) -> None:
        self.got: list[tuple[int, bytes]] = []

    def receive(self, channel: int, packet: bytes) -> None:
        self.got.append((channel, packet))

    def step(self) -> None:
        pass

    def needs_step(self) -> bool:
        return False


def test_ir_link_delivers_to_the_facing_connector_after_latency() -> None:
    structure = load_config("car7")
    world = PhysicsWorld(structure)
    try:
        inboxes = {mid: _Inbox() for mid in structure.modules}
        world.runtimes = inboxes  # type: ignore[assignment]
        for channel, (peer, peer_channel) in structure.neighbours(0).items():
            world.hals[0].send(channel, b"hello" + bytes([channel]))
            world.vm_tick()
            assert inboxes[peer].got == []  # latency: not in the same tick
            world.advance(0.1)
            assert inboxes[peer].got[-1] == (peer_channel, b"hello" + bytes([channel]))
        world.hals[0].send(next(c for c in range(8) if c not in structure.connected_channels(0)), b"x")
        assert world.network.counters.unconnected == 1
    finally:
        world.close()


def test_packet_loss_is_seeded() -> None:
    counts = []
    for _ in range(2):
        world = PhysicsWorld(load_config("car7"), packet_loss=0.5, seed=11)
        try:
            for k in range(40):
                world.hals[0].send(sorted(world.structure.connected_channels(0))[0], bytes([k]))
            counts.append(world.network.counters.as_dict())
        finally:
            world.close()
    assert counts[0] == counts[1] and 5 < counts[0]["dropped"] < 35


@pytest.mark.parametrize("distance,seen", [(0.18, True), (0.6, False)])
def test_front_wheel_sensor_sees_a_wall(distance: float, seen: bool) -> None:
    structure = load_config("car7")
    world = PhysicsWorld(structure, obstacles=parse_obstacle(f"wall:{distance}"))
    try:
        front_right = next(m for m, r in structure.expected_roles.items()
                           if r == "RightWheel" and structure.modules[m].position[1] > 0)
        assert world.hals[front_right].proximity(5) is False  # the first query starts sampling it
        world.advance(0.2)
        assert world.hals[front_right].proximity(5) is seen
        expected = [{"t": 0.05, "module": front_right, "sensor": 5}] if seen else []
        assert world.tracking.detections == expected
    finally:
        world.close()


def test_joint_turns_and_rotate_to() -> None:
    structure = load_config("car7")
    world = PhysicsWorld(structure)
    try:
        axle = next(m for m, r in structure.expected_roles.items() if r == "Axle")
        hal = world.hals[axle]
        hal.rotate_to(30)
        assert hal.is_turning()
        world.advance(1.5)
        assert hal.joint_angle_deg() == pytest.approx(30, abs=2)
        assert not hal.is_turning()
        wheel = next(m for m, r in structure.expected_roles.items() if r == "RightWheel")
        w = world.hals[wheel]
        w.rotate_continuously(1)
        world.advance(3.0)
        assert 0.4 < w.joint_turns() < 0.55  # one turn per 6 s
        w.stop_joint()
        assert not w.is_turning()
    finally:
        world.close()


def test_record_writes_an_animated_gif(tmp_path) -> None:  # noqa: ANN001
    from PIL import Image

    from sim.run import Options, simulate
    from tests.sim.helpers import obstacle_program

    out = tmp_path / "car.gif"
    report = simulate(obstacle_program(), load_config("car7"),
                      Options(obstacle="none", duration=5.0, record=str(out)))
    assert report["world"] == "physics"
    with Image.open(out) as gif:
        assert gif.n_frames >= 2 and gif.size == (320, 240)
