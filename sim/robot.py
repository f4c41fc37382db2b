"""Build a whole ATRON structure as ONE PyBullet multibody with few links.

Hemispheres joined by connections are rigidly attached, so each set of hemispheres glued
together by connections (a *rigid group*) is one link with a compound collision shape; the
modules' motorised revolute joints join the groups. The groups are walked as a spanning tree from
the entry module; a joint that would close a loop of groups is locked (its two groups merge), as
is a module whose two hemispheres lie in one group. The base is a tiny massless-ish anchor fixed
to the entry's group, so every group is a link whose frame PyBullet reports directly. Link
frames are aligned with the lattice frame at start, so a link's world orientation is the rotation
it made since the start.

Joint angle convention (shared with ``sim.joint``): positive = the physical south hemisphere
(connectors 4-7) turns clockwise seen from the north pole, i.e. about the vector from the centre
to the south pole. A PyBullet revolute joint whose axis points to its child hemisphere's pole
measures exactly this angle, whichever hemisphere is the child.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
import pybullet as pb

from sim import geometry as g
from sim import params
from sim import shapes as sh
from sim.poses import Matrix
from vm import navigation
from vm.lattice.structure import ModuleSpec, Structure

Node = tuple[int, int]  # (module id, virtual side PLUS/MINUS)
MAX_LINKS = 127  # PyBullet's limit per multibody


class RobotError(ValueError):
    """A structure PyBullet cannot build (one line)."""


@dataclass
class ModuleBody:
    id: int
    centre0: g.Vec3  # world position of the centre at start
    links: dict[int, int] = field(default_factory=dict)  # virtual side -> link index
    offsets: dict[int, g.Vec3] = field(default_factory=dict)  # side -> centre minus link origin, at start
    joint: int | None = None  # link index of this module's revolute joint, None if not motorised
    wheel_side: int = 0  # virtual side of the rubber-ringed free hemisphere, 0 = not a wheel
    body: int = -1  # the multibody that holds the module (both hemispheres: its joint joins them)
    # each hemisphere's frame in its link's frame; absent = identity. A hemisphere's frame is the
    # lattice frame at its module's creation, so connectors and poles are fixed in it; a link
    # rebuilt after a change of shape (sim.topology) may hold hemispheres turned against it.
    frames: dict[int, Matrix] = field(default_factory=dict)


@dataclass
class Robot:
    body: int  # the entry module's multibody
    modules: dict[int, ModuleBody]
    lift: float
    link_count: int
    shell_visual: dict[int, tuple[int, int]]  # module -> (link, visual shape index) of its sphere
    bodies: list[int] = field(default_factory=list)  # every multibody; one until the shape changes
    specs: dict[int, ModuleSpec] = field(default_factory=dict)  # each module as it was created

    def __post_init__(self) -> None:
        if not self.bodies:
            self.bodies = [self.body]


def wheel_side(structure: Structure, module_id: int) -> int:
    """Virtual side of the free hemisphere of a wheel-like module, or 0.

    A wheel is a module with a horizontal axis whose other hemisphere carries all connections.
    """
    spec = structure.modules[module_id]
    free = structure.free_hemisphere(module_id)
    if spec.axis == navigation.UP_DOWN or free is None:
        return 0
    return g.physical_side(spec, 4 * free)


def rigid_groups(structure: Structure) -> dict[Node, int]:
    """Group number of every hemisphere; connections glue hemispheres into one group."""
    parent: dict[Node, Node] = {}

    def find(n: Node) -> Node:
        while parent.setdefault(n, n) != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for mid in sorted(structure.modules):
        find((mid, g.PLUS))
        find((mid, g.MINUS))
    for link in structure.links():
        a = find((link.a, g.physical_side(structure.modules[link.a], link.a_physical)))
        b = find((link.b, g.physical_side(structure.modules[link.b], link.b_physical)))
        if a != b:
            parent[max(a, b)] = min(a, b)
    numbers: dict[Node, int] = {}
    out = {}
    for node in sorted(parent):
        out[node] = numbers.setdefault(find(node), len(numbers))
    return out


@dataclass
class _Plan:
    order: list[int]  # groups in depth-first order, root first
    parent_joint: dict[int, tuple[int, int]]  # group -> (parent group, module whose joint joins them)


def _plan(mids: Collection[int], entry: int, groups: dict[Node, int]) -> _Plan:
    """Spanning tree of rigid groups of the modules ``mids`` joined by module joints, rooted at
    the group of ``entry``.

    A joint that would close a loop of groups is locked (its two groups merge), and the tree is
    built again: a loop of joints can only turn in special cases, and loop-closing constraints
    cost PyBullet far more than the whole tree.
    """
    merged = {grp: grp for grp in set(groups.values())}

    def find(grp: int) -> int:
        while merged[grp] != grp:
            grp = merged[grp]
        return grp

    while True:
        parent_joint, closing = _spanning_tree(mids, entry, groups, find)
        if not closing:
            break
        for mid in closing:
            a, b = find(groups[(mid, g.PLUS)]), find(groups[(mid, g.MINUS)])
            if a != b:
                merged[max(a, b)] = min(a, b)
    for node in groups:  # callers see the merged groups
        groups[node] = find(groups[node])
    root = groups[(entry, g.PLUS)]
    children: dict[int, list[int]] = {}
    for child, (par, _) in sorted(parent_joint.items()):
        children.setdefault(par, []).append(child)
    order, stack = [], [root]
    while stack:  # PyBullet renumbers links depth-first, so give them so
        grp = stack.pop()
        order.append(grp)
        stack.extend(reversed(children.get(grp, [])))
    return _Plan(order, parent_joint)


def _spanning_tree(mids: Collection[int], entry: int, groups: dict[Node, int],
                   find: Callable[[int], int]) -> tuple[dict[int, tuple[int, int]], list[int]]:
    """(group -> (parent group, joining module)), and the modules whose joint closes a loop."""
    edges: dict[int, list[tuple[int, int]]] = {}
    for mid in sorted(mids):
        a, b = find(groups[(mid, g.PLUS)]), find(groups[(mid, g.MINUS)])
        if a != b:
            edges.setdefault(a, []).append((b, mid))
            edges.setdefault(b, []).append((a, mid))
    root = find(groups[(entry, g.PLUS)])
    parent_joint: dict[int, tuple[int, int]] = {}
    seen, used = {root}, set()
    queue = deque([root])
    while queue:
        grp = queue.popleft()
        for other, mid in sorted(edges.get(grp, [])):
            if other not in seen:
                seen.add(other)
                used.add(mid)
                parent_joint[other] = (grp, mid)
                queue.append(other)
    closing = sorted({mid for lst in edges.values() for _, mid in lst} - used)
    return parent_joint, closing


def _lift(structure: Structure) -> float:
    lowest = math.inf
    for mid, spec in structure.modules.items():
        z = g.lattice_to_world(spec.position)[2]
        r = params.RING_RADIUS if wheel_side(structure, mid) else params.MODULE_RADIUS
        lowest = min(lowest, z - r)
    return -lowest + params.SPAWN_CLEARANCE


def rigid_part_count(structure: Structure) -> int:
    """How many rigid parts (PyBullet links) ``build_robot`` would make of ``structure``."""
    return len(_plan(structure.modules, structure.entry, rigid_groups(structure)).order)


def build_robot(structure: Structure, client: int, *, visuals: bool = False) -> Robot:
    """Create the structure's multibody in ``client``; the entry module's centre at x = y = 0."""
    lift = _lift(structure)
    modules = {mid: ModuleBody(mid, g.add(g.lattice_to_world(s.position), (0.0, 0.0, lift)),
                               wheel_side=wheel_side(structure, mid))
               for mid, s in structure.modules.items()}
    shell_visual: dict[int, tuple[int, int]] = {}
    built = assemble_links(structure.modules, structure.entry, rigid_groups(structure), StartPoses(modules),
                           modules, shell_visual, client, visuals=visuals,
                           name=structure.name or "structure")
    return Robot(built.body, modules, lift, len(built.plan.order), shell_visual, [built.body],
                 dict(structure.modules))


Quat = tuple[float, float, float, float]
IDENTITY: Quat = (0.0, 0.0, 0.0, 1.0)


class Poses(Protocol):
    """Where the hemispheres of a body are: at the start (``StartPoses``) or in the world now
    (``sim.topology``, after a change of shape). A link's frame is the frame of one of its
    hemispheres, its *reference*."""

    def base(self, ref: Node) -> tuple[g.Vec3, Quat]:
        """World position and orientation of the root link's frame, whose reference is ``ref``."""
        ...

    def place(self, ref: Node, node: Node) -> tuple[g.Vec3, np.ndarray | None]:
        """Hemisphere ``node``'s centre and frame in the link frame of ``ref`` (None: that frame)."""
        ...

    def joint(self, parent: Node, ref: Node) -> tuple[g.Vec3, Quat]:
        """Position and orientation of the link frame of ``ref`` in the link frame of ``parent``."""
        ...


@dataclass
class StartPoses:
    """The lattice poses a structure starts in: every hemisphere frame is the world frame."""

    modules: dict[int, ModuleBody]

    def base(self, ref: Node) -> tuple[g.Vec3, Quat]:
        return self.modules[ref[0]].centre0, IDENTITY

    def place(self, ref: Node, node: Node) -> tuple[g.Vec3, np.ndarray | None]:
        return g.sub(self.modules[node[0]].centre0, self.modules[ref[0]].centre0), None

    def joint(self, parent: Node, ref: Node) -> tuple[g.Vec3, Quat]:
        return g.sub(self.modules[ref[0]].centre0, self.modules[parent[0]].centre0), IDENTITY


@dataclass
class Assembly:
    body: int
    plan: _Plan
    ref: dict[int, Node]  # group -> the hemisphere whose frame is its link's frame
    axes: list[g.Vec3]  # each link's joint axis, in its own frame


def assemble_links(specs: dict[int, ModuleSpec], entry: int, groups: dict[Node, int], poses: Poses,
                   modules: dict[int, ModuleBody], shell_visual: dict[int, tuple[int, int]], client: int,
                   *, visuals: bool, name: str) -> Assembly:
    """One multibody of the modules of ``specs`` (each as created), hemispheres grouped by ``groups``
    into rigid links, at ``poses``; the root link is fixed to a tiny anchor at the reference of the
    group of ``entry``. Fills in the ``modules``' links, offsets, frames, joint and body, and
    ``shell_visual``; every joint's motor holds still."""
    plan = _plan(specs, entry, groups)
    if len(plan.order) + 1 > MAX_LINKS:
        raise RobotError(f"{name}: {len(plan.order)} rigid parts exceed PyBullet's {MAX_LINKS} links "
                         "per body")
    members: dict[int, list[Node]] = {}
    for node, grp in sorted(groups.items()):
        members.setdefault(grp, []).append(node)
    ref: dict[int, Node] = {plan.order[0]: (entry, g.PLUS)}
    for grp, (_, mid) in plan.parent_joint.items():
        ref[grp] = next(n for n in members[grp] if n[0] == mid)  # the joint's hemisphere in the group
    link_of = {grp: i for i, grp in enumerate(plan.order)}
    cols, vis, pos, orns, inert_pos, inert_orn = ([] for _ in range(6))
    masses, inertias, parents, types, axes = ([] for _ in range(5))
    ring_axes: dict[int, int] = {}  # link -> axis of the wheel whose ring it carries
    for i, grp in enumerate(plan.order):
        parts, shown = [], 0
        for node in members[grp]:
            mid, side = node
            mb = modules[mid]
            offset, turn = poses.place(ref[grp], node)
            mb.links[side], mb.offsets[side] = i, offset
            axis, pole_side = specs[mid].axis, side
            if turn is not None:
                if not np.allclose(turn, np.eye(3)):
                    mb.frames[side] = tuple(tuple(r) for r in turn.tolist())
                axis, pole_side = _axis_side(turn @ np.array(g.hemisphere_pole(axis, side)))
            if mb.wheel_side == side:
                kind = "ring"
                ring_axes[i] = axis
            elif side == (-mb.wheel_side if mb.wheel_side else g.PLUS):
                kind = "shell"  # one sphere per module: it is symmetric about the joint axis
                shell_visual[mid] = (i, shown)
            else:
                kind = "none"
            shown += kind != "none"
            parts.append(sh.Part(offset, axis, pole_side, kind))
        cols.append(sh.compound_collision(parts, client))
        vis.append(sh.compound_visual(parts, client) if visuals else -1)
        mass, com, diag, orn = sh.mass_properties(parts)
        masses.append(mass)
        inert_pos.append(com)
        inert_orn.append(orn)
        inertias.append(diag)
        if i == 0:  # the root link, fixed to the anchor
            parents.append(0)
            types.append(pb.JOINT_FIXED)
            axes.append((0.0, 0.0, 1.0))
            pos.append((0.0, 0.0, 0.0))
            orns.append(IDENTITY)
            continue
        par, mid = plan.parent_joint[grp]
        parents.append(link_of[par] + 1)
        types.append(pb.JOINT_REVOLUTE)
        axes.append(g.hemisphere_pole(specs[mid].axis, ref[grp][1]))  # the child's own pole
        where, turned = poses.joint(ref[par], ref[grp])
        pos.append(where)
        orns.append(turned)
        modules[mid].joint = i
    n = len(plan.order)
    base_position, base_orientation = poses.base(ref[plan.order[0]])
    body = pb.createMultiBody(
        baseMass=params.ANCHOR_MASS, baseCollisionShapeIndex=-1, baseVisualShapeIndex=-1,
        basePosition=base_position, baseOrientation=base_orientation,
        linkMasses=masses, linkCollisionShapeIndices=cols, linkVisualShapeIndices=vis,
        linkPositions=pos, linkOrientations=orns, linkInertialFramePositions=inert_pos,
        linkInertialFrameOrientations=inert_orn, linkParentIndices=parents,
        linkJointTypes=types, linkJointAxis=axes, physicsClientId=client)
    if body < 0 or pb.getNumJoints(body, physicsClientId=client) != n:
        raise RobotError(f"{name}: PyBullet could not build the body")
    pb.changeDynamics(body, -1, localInertiaDiagonal=(params.ANCHOR_INERTIA,) * 3, physicsClientId=client)
    _set_dynamics(body, inertias, ring_axes, client)
    for mid in specs:
        mb = modules[mid]
        mb.body = body
        if mb.joint is not None:
            pb.setJointMotorControl2(body, mb.joint, pb.VELOCITY_CONTROL, targetVelocity=0.0,
                                     force=params.JOINT_MAX_TORQUE, physicsClientId=client)
    return Assembly(body, plan, ref, axes)


def _axis_side(pole: np.ndarray) -> tuple[int, int]:
    """The lattice axis and side (PLUS/MINUS) of an axis-aligned pole vector."""
    i = int(np.argmax(np.abs(pole)))
    axis = next(a for a, vec in g.AXIS_VECTORS.items() if vec[i])
    return axis, (g.PLUS if pole[i] > 0 else g.MINUS)


def _set_dynamics(body: int, inertias: list[g.Vec3], ring_axes: dict[int, int], client: int) -> None:
    """Inertia and contact of every link; ``ring_axes`` gives the axis of each link with a ring."""
    for i, diag in enumerate(inertias):
        ring = i in ring_axes
        if ring and params.RING_AXIAL_FRICTION_SCALE != 1.0:
            axis = g.AXIS_VECTORS[ring_axes[i]]
            scale = tuple(params.RING_AXIAL_FRICTION_SCALE if a else 1.0 for a in axis)
            pb.changeDynamics(body, i, anisotropicFriction=scale, physicsClientId=client)
        pb.changeDynamics(body, i, localInertiaDiagonal=diag, restitution=params.RESTITUTION,
                          lateralFriction=params.RING_FRICTION if ring else params.SHELL_FRICTION,
                          rollingFriction=params.RING_ROLLING_FRICTION if ring else 0.0,
                          spinningFriction=params.RING_SPINNING_FRICTION if ring else 0.0,
                          linearDamping=0.0, angularDamping=0.0, jointDamping=params.JOINT_DAMPING,
                          physicsClientId=client)
