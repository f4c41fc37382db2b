"""A robot whose shape changed: its multibodies built again from where its parts are now.

While nothing changes a structure is one multibody (``sim.robot``), the fast case. A latch made
or undone, a module attached or detached changes which hemispheres are glued into one rigid part
and which parts still make one robot; then the bodies are built again from the current world pose
and velocity of every hemisphere: nothing jumps. Each rigid part's link frame is the frame of one
of its hemispheres as it is now; the others sit in it at their lattice offsets and quarter-turn
orientations (snapped: parts glued together are on the lattice relative to each other, up to the
few millimetres a closing latch pulls them by). A joint's new zero is its current angle
(``sim.joint`` keeps the offset, so angles and turn counts go on). A body is assembled by
``sim.robot.assemble_links`` as at the start; only the poses differ (``WorldPoses``: where the
hemispheres are now).

A split makes several multibodies: the part holding the entry module, and each part cut off (it
falls or lies where it is, and its modules go on running).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from sim import geometry as g
from sim import params
from sim import shapes as sh
from sim.poses import quat_matrix
from sim.robot import Assembly, ModuleBody, Node, Quat, Robot, _plan, assemble_links
from vm.lattice.structure import ModuleSpec

Latch = tuple[int, int, int, int]  # module, physical connector, module, physical connector


@dataclass
class HemiState:
    """One hemisphere in the world now: its centre, its frame's rotation, their velocities."""

    centre: np.ndarray
    rot: np.ndarray  # 3x3, hemisphere frame -> world
    velocity: np.ndarray  # of the centre
    spin: np.ndarray  # angular velocity


def hemisphere_states(robot: Robot, client: int) -> dict[Node, HemiState]:
    out: dict[Node, HemiState] = {}
    for body in robot.bodies:
        mods = [mb for mb in robot.modules.values() if mb.body == body]
        links = sorted({mb.links[s] for mb in mods for s in (g.PLUS, g.MINUS)})
        states = pb.getLinkStates(body, links, computeLinkVelocity=1, physicsClientId=client)
        by_link = dict(zip(links, states, strict=True))
        for mb in mods:
            for side in (g.PLUS, g.MINUS):
                st = by_link[mb.links[side]]
                m = np.array(quat_matrix(st[5]))
                centre = np.array(st[4]) + m @ np.array(mb.offsets[side])
                spin = np.array(st[7])
                velocity = np.array(st[6]) + np.cross(spin, centre - np.array(st[0]))  # st[6]: the COM's
                frame = np.array(mb.frames[side]) if side in mb.frames else np.eye(3)
                out[(mb.id, side)] = HemiState(centre, m @ frame, velocity, spin)
    return out


def snap_rotation(m: np.ndarray) -> np.ndarray:
    """The quarter-turn rotation (a signed permutation) nearest ``m``."""
    out = np.zeros((3, 3))
    for i in range(3):
        j = int(np.argmax(np.abs(m[i])))
        out[i, j] = 1.0 if m[i, j] > 0 else -1.0
    if sorted(np.argmax(np.abs(out), axis=1).tolist()) != [0, 1, 2] or np.linalg.det(out) < 0:
        return m  # far from any quarter turn: keep it as it is
    return out


def snap_offset(v: np.ndarray) -> np.ndarray:
    u = params.LATTICE_UNIT
    return np.round(v / u) * u


def glue_nodes(specs: dict[int, ModuleSpec], latches: Iterable[Latch]) -> list[tuple[Node, Node]]:
    return [((a, g.physical_side(specs[a], pa)), (b, g.physical_side(specs[b], pb_)))
            for a, pa, b, pb_ in latches]


def _groups(mids: list[int], glue: list[tuple[Node, Node]]) -> dict[Node, Node]:
    """Union-find root of every hemisphere of ``mids`` (glued hemispheres share one)."""
    parent: dict[Node, Node] = {}

    def find(n: Node) -> Node:
        while parent.setdefault(n, n) != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for mid in mids:
        find((mid, g.PLUS))
        find((mid, g.MINUS))
    for a, b in glue:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    return {n: find(n) for n in list(parent)}


def components(mids: list[int], glue: list[tuple[Node, Node]]) -> list[list[int]]:
    """The modules that still make one robot, part by part (a module's joint holds its halves)."""
    roots = _groups(mids, glue)
    parent = {mid: mid for mid in mids}

    def find(m: int) -> int:
        while parent[m] != m:
            m = parent[m]
        return m

    by_root: dict[Node, int] = {}
    for node, root in sorted(roots.items()):
        other = by_root.setdefault(root, node[0])
        a, b = find(other), find(node[0])
        if a != b:
            parent[max(a, b)] = min(a, b)
    parts: dict[int, list[int]] = {}
    for mid in sorted(mids):
        parts.setdefault(find(mid), []).append(mid)
    return sorted(parts.values())


def rebuild(robot: Robot, specs: dict[int, ModuleSpec], latches: Iterable[Latch], entry: int,
            client: int, states: dict[Node, HemiState], *, visuals: bool = False) -> Robot:
    """New multibodies for the modules of ``specs`` (each as created: its hemisphere frames),
    glued by ``latches``, at the poses and velocities of ``states``; the old bodies are removed.
    ``robot.modules`` gives each module's wheel ring; a module not in it has none."""
    modules: dict[int, ModuleBody] = {}
    shell_visual: dict[int, tuple[int, int]] = {}
    bodies: list[int] = []
    links = 0
    main = -1
    for part, root_mid, groups in _bodies(specs, latches, entry):
        for mid in part:
            old = robot.modules.get(mid)
            centre0 = old.centre0 if old else tuple(states[(mid, g.PLUS)].centre.tolist())
            modules[mid] = ModuleBody(mid, centre0, wheel_side=old.wheel_side if old else 0)
        built = assemble_links({mid: specs[mid] for mid in part}, root_mid, groups, WorldPoses(states),
                               modules, shell_visual, client, visuals=visuals, name="the changed structure")
        _set_velocities(built, states, client)
        bodies.append(built.body)
        links += len(built.plan.order)
        if root_mid == entry:
            main = built.body
    for old in robot.bodies:
        pb.removeBody(old, physicsClientId=client)
    return Robot(main if main >= 0 else bodies[0], modules, robot.lift, links, shell_visual, bodies,
                 dict(specs))


def _bodies(specs: dict[int, ModuleSpec], latches: Iterable[Latch],
            entry: int) -> Iterator[tuple[list[int], int, dict[Node, int]]]:
    """Each multibody the modules make: its modules, its root module, its rigid groups."""
    glue = glue_nodes(specs, latches)
    for part in components(sorted(specs), glue):
        mine = set(part)
        roots = _groups(part, [(a, b) for a, b in glue if a[0] in mine])
        numbers: dict[Node, int] = {}
        groups = {node: numbers.setdefault(r, len(numbers)) for node, r in sorted(roots.items())}
        yield part, entry if entry in mine else part[0], groups


def largest_body(specs: dict[int, ModuleSpec], latches: Iterable[Latch], entry: int) -> int:
    """How many rigid parts (links) the largest multibody ``rebuild`` would make has."""
    bodies = _bodies(specs, latches, entry)
    return max((len(_plan(part, root, groups).order) for part, root, groups in bodies), default=0)


@dataclass
class WorldPoses:
    """Where the hemispheres are now (``sim.robot.Poses``). A hemisphere sits in its link at its
    lattice offset and quarter-turn orientation, snapped; a joint stands at whatever angle it has."""

    states: dict[Node, HemiState]

    def base(self, ref: Node) -> tuple[g.Vec3, Quat]:
        st = self.states[ref]
        return tuple(st.centre.tolist()), sh.matrix_to_quat(st.rot)

    def place(self, ref: Node, node: Node) -> tuple[g.Vec3, np.ndarray | None]:
        r, st = self.states[ref], self.states[node]
        offset = snap_offset(r.rot.T @ (st.centre - r.centre))
        return tuple(offset.tolist()), snap_rotation(r.rot.T @ st.rot)

    def joint(self, parent: Node, ref: Node) -> tuple[g.Vec3, Quat]:
        p, r = self.states[parent], self.states[ref]
        where = snap_offset(p.rot.T @ (r.centre - p.centre))
        return tuple(where.tolist()), sh.matrix_to_quat(p.rot.T @ r.rot)


def _set_velocities(built: Assembly, states: dict[Node, HemiState], client: int) -> None:
    """The new body moves on as its hemispheres moved: the root's velocity, each joint's rate."""
    plan, ref = built.plan, built.ref
    root = states[ref[plan.order[0]]]
    pb.resetBaseVelocity(built.body, tuple(root.velocity.tolist()), tuple(root.spin.tolist()),
                         physicsClientId=client)
    link_of = {grp: i for i, grp in enumerate(plan.order)}
    for grp, (par, _) in plan.parent_joint.items():
        axis = states[ref[grp]].rot @ np.array(built.axes[link_of[grp]])
        rate = float((states[ref[grp]].spin - states[ref[par]].spin) @ axis)
        pb.resetJointState(built.body, link_of[grp], 0.0, rate, physicsClientId=client)
