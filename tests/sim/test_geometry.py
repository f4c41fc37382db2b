"""Connector placement: physical connector p sits where the VM's navigation says, and touching
connectors of neighbours meet, for the shipped configurations and random structures."""

from __future__ import annotations

import numpy as np
import pybullet as pb
import pytest

from sim import geometry as g
from sim import params
from sim.config import load_config, random_structure
from sim.poses import link_poses, to_world
from sim.robot import build_robot, rigid_groups
from sim.sensors import Sensors
from sim.shapes import Part, mass_properties, matrix_to_quat
from tests.sim import helpers  # noqa: F401  (quiet PyBullet import)
from vm import navigation

STRUCTURES = ["car7", "car11", "car8-cyclic", "car17-wide", "snake6"]


def _connector_positions(structure) -> dict[tuple[int, int], np.ndarray]:  # noqa: ANN001
    client = pb.connect(pb.DIRECT)
    try:
        robot = build_robot(structure, client)
        sensors = Sensors(robot, client)
        poses = link_poses(robot.body, {link for link, _, _ in sensors._rays.values()}, client)
        return {key: np.array(to_world(poses[link], origin))
                for key, (link, origin, _) in sensors._rays.items()}
    finally:
        pb.disconnect(client)


@pytest.mark.parametrize("name", STRUCTURES + [f"random{5 + 2 * i}-{100 + i}" for i in range(20)])
def test_touching_connectors_meet(name: str) -> None:
    if name.startswith("random"):
        n, seed = name[6:].split("-")
        structure = random_structure(int(n), int(seed))
    else:
        structure = load_config(name)
    where = _connector_positions(structure)
    for link in structure.links():
        a, b = where[(link.a, link.a_physical)], where[(link.b, link.b_physical)]
        # sensors sit 2 mm out from each shell; centres are 0.113 m apart, shells 3 mm apart
        assert np.linalg.norm(a - b) < 0.01, (name, link)


@pytest.mark.parametrize("axis", navigation.AXES)
def test_connector_directions_follow_the_navigation_table(axis: int) -> None:
    for v in range(8):
        d = np.array(g.connector_direction(axis, v))
        off = np.array(navigation.offset(axis, v), dtype=float)
        assert np.allclose(d, off / np.linalg.norm(off))
        # 45° from the equator: the component along the joint axis is cos 45°
        assert abs(abs(d @ np.array(g.AXIS_VECTORS[axis])) - np.sqrt(0.5)) < 1e-9
        assert (v < 4) == (d @ np.array(g.AXIS_VECTORS[axis]) > 0)


def test_mount_places_physical_connectors() -> None:
    structure = load_config("car7")
    for mid, spec in structure.modules.items():
        for p in range(8):
            expected = structure.physical_direction(mid, p)
            d = np.array(g.physical_connector_direction(spec, p))
            assert np.allclose(d, np.array(expected) / np.linalg.norm(expected))


def test_wheels_get_rings_and_only_rings_touch_the_ground() -> None:
    structure = load_config("car7")
    client = pb.connect(pb.DIRECT)
    try:
        robot = build_robot(structure, client)
        wheels = {mid for mid, mb in robot.modules.items() if mb.wheel_side}
        assert wheels == {mid for mid, r in structure.expected_roles.items() if r and "Wheel" in r}
        lowest_shell = min(g.lattice_to_world(s.position)[2] for s in structure.modules.values())
        assert lowest_shell + robot.lift - params.MODULE_RADIUS > 0.002
    finally:
        pb.disconnect(client)


def test_cars_have_few_links_and_no_locked_joints() -> None:
    for name in ("car7", "car8-cyclic", "car17-wide"):
        structure = load_config(name)
        groups = rigid_groups(structure)
        assert all(groups[(m, 1)] != groups[(m, -1)] for m in structure.modules), name
    client = pb.connect(pb.DIRECT)
    try:
        robot = build_robot(load_config("car7"), client)
        assert robot.link_count == 8
        assert all(mb.joint is not None for mb in robot.modules.values())
    finally:
        pb.disconnect(client)


def test_mass_properties_of_one_module() -> None:
    parts = [Part((0.0, 0.0, 0.0), navigation.EAST_WEST, 1, "shell"),
             Part((0.0, 0.0, 0.0), navigation.EAST_WEST, -1, "none")]
    mass, com, diag, _ = mass_properties(parts)
    assert mass == pytest.approx(params.MODULE_MASS)
    assert np.allclose(com, (0, 0, 0))
    assert all(d > 0 for d in diag)


def test_matrix_to_quat_round_trip() -> None:
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        m = np.array(pb.getMatrixFromQuaternion(q.tolist())).reshape(3, 3)
        back = np.array(matrix_to_quat(m))
        assert np.allclose(back, q) or np.allclose(back, -q)
