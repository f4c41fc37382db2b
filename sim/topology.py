"""A robot whose shape changed: its multibodies built again from where its parts are now.

While nothing changes a structure is one multibody (``sim.robot``), the fast case. A latch made
or undone, a module attached or detached changes which hemispheres are glued into one rigid part
and which parts still make one robot; then the bodies are built again from the current world pose
and velocity of every hemisphere: nothing jumps. Each rigid part's link frame is the frame of one
of its hemispheres as it is now; the others sit in it at their lattice offsets and quarter-turn
orientations (snapped: parts glued together are on the lattice relative to each other, up to the
few millimetres a closing latch pulls them by). A joint's new zero is its current angle
(``sim.joint`` keeps the offset, so angles and turn counts go on).

A split makes several multibodies: the part holding the entry module, and each part cut off (it
falls or lies where it is, and its modules go on running).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from sim import geometry as g
from sim import params
from sim import shapes as sh
from sim.poses import quat_matrix
from sim.robot import MAX_LINKS, ModuleBody, Node, Robot, RobotError, _plan, _set_dynamics
from vm.lattice.structure import ModuleSpec

Latch = tuple[int, int, int, int]  # module, physical connector, module, physical connector


@dataclass
class HemiState:
    """One hemisphere in the world now: its centre, its frame's rotation, their velocities."""

    centre: np.ndarray
    rot: np.ndarray  # 3x3, hemisphere frame -> world
    velocity: np.ndarray  # of the centre
    spin: np.ndarray  # angular velocity


@dataclass
class _Topo:
    """The two things ``sim.robot._plan`` reads of a structure."""

    modules: dict[int, None]
    entry: int


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


def _axis_side(pole: np.ndarray) -> tuple[int, int]:
    i = int(np.argmax(np.abs(pole)))
    axis = next(a for a, vec in g.AXIS_VECTORS.items() if vec[i])
    return axis, (g.PLUS if pole[i] > 0 else g.MINUS)


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
    glue = glue_nodes(specs, latches)
    mids = sorted(specs)
    modules: dict[int, ModuleBody] = {}
    shell_visual: dict[int, tuple[int, int]] = {}
    bodies: list[int] = []
    links = 0
    main = -1
    for part in components(mids, glue):
        mine = set(part)
        root_mid = entry if entry in mine else part[0]
        roots = _groups(part, [(a, b) for a, b in glue if a[0] in mine])
        numbers: dict[Node, int] = {}
        groups = {node: numbers.setdefault(r, len(numbers)) for node, r in sorted(roots.items())}
        body, count = _build_part(robot, specs, _Topo(dict.fromkeys(part), root_mid), groups, states,
                                  modules, shell_visual, client, visuals)
        bodies.append(body)
        links += count
        if root_mid == entry:
            main = body
    for old in robot.bodies:
        pb.removeBody(old, physicsClientId=client)
    return Robot(main if main >= 0 else bodies[0], modules, robot.lift, links, shell_visual, bodies,
                 dict(specs))


def _build_part(robot: Robot, specs: dict[int, ModuleSpec], topo: _Topo, groups: dict[Node, int],
                states: dict[Node, HemiState], modules: dict[int, ModuleBody],
                shell_visual: dict[int, tuple[int, int]], client: int, visuals: bool) -> tuple[int, int]:
    plan = _plan(topo, groups)  # type: ignore[arg-type]  # reads .modules and .entry only
    if len(plan.order) + 1 > MAX_LINKS:
        raise RobotError(f"{len(plan.order)} rigid parts exceed PyBullet's {MAX_LINKS} links per body")
    members: dict[int, list[Node]] = {}
    for node, grp in sorted(groups.items()):
        members.setdefault(grp, []).append(node)
    ref: dict[int, Node] = {plan.order[0]: (topo.entry, g.PLUS)}
    for grp, (_, mid) in plan.parent_joint.items():
        ref[grp] = next(n for n in members[grp] if n[0] == mid)
    origin = {grp: states[node].centre for grp, node in ref.items()}
    frame = {grp: states[node].rot for grp, node in ref.items()}
    link_of = {grp: i for i, grp in enumerate(plan.order)}
    for mid in topo.modules:
        old = robot.modules.get(mid)
        modules[mid] = ModuleBody(mid, old.centre0 if old else tuple(states[(mid, g.PLUS)].centre.tolist()),
                                  wheel_side=old.wheel_side if old else 0)
    cols, vis, pos, orns, inert_pos, inert_orn = ([] for _ in range(6))
    masses, inertias, parents, types, axes = ([] for _ in range(5))
    ring_axes: dict[int, int] = {}
    for i, grp in enumerate(plan.order):
        parts, shown = [], 0
        rot_t = frame[grp].T
        for node in members[grp]:
            mid, side = node
            mb, spec = modules[mid], specs[mid]
            offset = snap_offset(rot_t @ (states[node].centre - origin[grp]))
            turn = snap_rotation(rot_t @ states[node].rot)
            mb.links[side], mb.offsets[side] = i, tuple(offset.tolist())
            if not np.allclose(turn, np.eye(3)):
                mb.frames[side] = tuple(tuple(r) for r in turn.tolist())
            axis, pole_side = _axis_side(turn @ np.array(g.hemisphere_pole(spec.axis, side)))
            if mb.wheel_side == side:
                kind = "ring"
                ring_axes[i] = axis
            elif side == (-mb.wheel_side if mb.wheel_side else g.PLUS):
                kind = "shell"
                shell_visual[mid] = (i, shown)
            else:
                kind = "none"
            shown += kind != "none"
            parts.append(sh.Part(tuple(offset.tolist()), axis, pole_side, kind))
        cols.append(sh.compound_collision(parts, client))
        vis.append(sh.compound_visual(parts, client) if visuals else -1)
        mass, com, diag, orn = sh.mass_properties(parts)
        masses.append(mass)
        inert_pos.append(com)
        inert_orn.append(orn)
        inertias.append(diag)
        if i == 0:
            parents.append(0)
            types.append(pb.JOINT_FIXED)
            axes.append((0.0, 0.0, 1.0))
            pos.append((0.0, 0.0, 0.0))
            orns.append((0.0, 0.0, 0.0, 1.0))
            continue
        par, mid = plan.parent_joint[grp]
        parents.append(link_of[par] + 1)
        types.append(pb.JOINT_REVOLUTE)
        axes.append(g.hemisphere_pole(specs[mid].axis, ref[grp][1]))  # the child's own pole
        pos.append(tuple(snap_offset(frame[par].T @ (origin[grp] - origin[par])).tolist()))
        orns.append(sh.matrix_to_quat(frame[par].T @ frame[grp]))  # exact: a joint stands at any angle
        modules[mid].joint = i
    n = len(plan.order)
    body = pb.createMultiBody(
        baseMass=params.ANCHOR_MASS, baseCollisionShapeIndex=-1, baseVisualShapeIndex=-1,
        basePosition=tuple(origin[plan.order[0]].tolist()),
        baseOrientation=sh.matrix_to_quat(frame[plan.order[0]]),
        linkMasses=masses, linkCollisionShapeIndices=cols, linkVisualShapeIndices=vis,
        linkPositions=pos, linkOrientations=orns, linkInertialFramePositions=inert_pos,
        linkInertialFrameOrientations=inert_orn, linkParentIndices=parents,
        linkJointTypes=types, linkJointAxis=axes, physicsClientId=client)
    if body < 0 or pb.getNumJoints(body, physicsClientId=client) != n:
        raise RobotError("PyBullet could not build a changed structure")
    pb.changeDynamics(body, -1, localInertiaDiagonal=(params.ANCHOR_INERTIA,) * 3, physicsClientId=client)
    _set_dynamics(body, inertias, ring_axes, client)
    root = states[ref[plan.order[0]]]
    pb.resetBaseVelocity(body, tuple(root.velocity.tolist()), tuple(root.spin.tolist()),
                         physicsClientId=client)
    for grp, (par, _) in plan.parent_joint.items():
        axis = frame[grp] @ np.array(axes[link_of[grp]])
        rate = float((states[ref[grp]].spin - states[ref[par]].spin) @ axis)
        pb.resetJointState(body, link_of[grp], 0.0, rate, physicsClientId=client)
    for mid in topo.modules:
        modules[mid].body = body
        if modules[mid].joint is not None:
            pb.setJointMotorControl2(body, modules[mid].joint, pb.VELOCITY_CONTROL, targetVelocity=0.0,
                                     force=params.JOINT_MAX_TORQUE, physicsClientId=client)
    return body, n

