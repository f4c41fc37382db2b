"""Structures that change, in the physics world (docs/simulator.md "Structures that change").

The structure (``vm.lattice.structure``) is the one truth about shape; ``Shape`` is how the
physics world keeps to it:

- a module's **connect** latches only if the two connector points are within
  ``params.LATCH_DISTANCE`` of each other in the world (USSR's ATRON: 3 cm); then the structure's
  own checks (male onto female, free) decide;
- a **disconnect** is the structure's unlatch; a split leaves parts that go on running;
- a **quarter turn** is checked by the structure first (loop, sweep through a module or the
  ground), then the joint turns its load under gravity with the ATRON's torque. When it has
  reached its angle, the cells the carried modules reached are read from the bodies: within
  ``params.SNAP_DISTANCE`` of the cells the structure computes, the structure applies the turn;
  otherwise, or when the joint stalled (the load was more than it could lift), the turn failed;
- **outside changes** (a module detached, attached, stopped for good) are the structure's remove
  and add, or a module that is no longer stepped.

Every change of the structure that happened (whoever made it) is heard here; at the end of the
tick the bodies are built again from where they are (``sim.topology``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
import pybullet as pb

from sim import geometry as g
from sim import params
from sim.frames import cell_of, connector_direction, node_of, structure_frame
from sim.joint import PhysicsJoint
from sim.robot import MAX_LINKS
from sim.topology import HemiState, hemisphere_states, largest_body, rebuild
from vm.lattice import changes
from vm.lattice.geometry import placement
from vm.lattice.motion import quarter
from vm.lattice.structure import ModuleSpec, Structure

if TYPE_CHECKING:
    from sim.world import PhysicsWorld


class Shape:
    def __init__(self, world: PhysicsWorld) -> None:
        self.world = world
        self.turns: dict[int, tuple[int, int]] = {}  # module -> (quarters, moving side) under way
        self.heard: list[Any] = []  # changes of the structure the bodies do not follow yet
        self.busy = False  # something for ``tick``
        self.rebuilds = 0  # bodies built again so often (the debugger's saved states fit none then)
        world.structure.listeners.append(self.hear)

    # ---- what modules do (through sim.hal) ---------------------------------------------------
    def act(self, mid: int, kind: str, arg: int) -> int | None:
        """Start a module's action: 1 done, 0 failed (said why), None under way (a turn)."""
        s = self.world.structure
        if mid in self.turns or mid not in s.modules or mid in self.world.stopped:
            reason = "the module is turning" if mid in self.turns else "the module was taken away"
            self.say(mid, f"{'rotation' if kind == 'turn' else kind}_failed", {"reason": reason})
            return 0
        if kind == "connect":
            gap = self.gap(mid, arg) if isinstance(arg, int) and 0 <= arg <= 7 else None
            if gap is not None and gap > params.LATCH_DISTANCE:
                self.say(mid, "connect_failed", {"connector": arg, "cause": "not_aligned", "reason": (
                    f"connector {arg} of module {mid} is {gap * 100:.1f} cm from the connector it faces; "
                    f"a latch closes within {params.LATCH_DISTANCE * 100:g} cm")})
                return 0
            if self._beyond_links(mid, "connect_failed", lambda t: t.latch(mid, arg), {"connector": arg}):
                return 0
            return self._done(s.latch(mid, arg), "connect")
        if kind == "disconnect":
            if self._beyond_links(mid, "disconnect_failed", lambda t: t.unlatch(mid, arg),
                                  {"connector": arg}):
                return 0
            return self._done(s.unlatch(mid, arg), "disconnect")
        if kind == "turn":
            return self._turn(mid, arg)
        raise ValueError(f"unknown action {kind!r}")

    def _turn(self, mid: int, quarters: int) -> int | None:
        check = self.world.structure.rotate(mid, quarters, apply=False)
        if not check.ok:
            return self._done(check, "rotation")
        if quarters == 0:
            return 1
        joint = self.world.joints[mid]
        if joint.joint is None:  # the structure sees the loop first; this is a guard
            self.say(mid, "rotation_failed", {"quarters": quarters, "cause": "loop",
                                              "reason": f"module {mid}'s joint is locked in a loop"})
            return 0
        joint.turn_quarters(quarters)
        self.turns[mid] = (quarters, check.moving or 0)
        self.busy = True
        self.say(mid, "rotation_start", {"quarters": quarters, "moving": _HEMISPHERES[check.moving or 0],
                                         "carried": list(check.moved)})
        return None

    def _done(self, change: Any, kind: str) -> int:
        if not change.ok:  # the structure tells its listeners only what happened
            self.say(change.module, f"{kind}_failed", {**_detail(change), "cause": change.cause,
                                                       "reason": change.reason})
        return int(change.ok)

    def gap(self, mid: int, physical: int) -> float | None:
        """World distance from connector ``physical`` of ``mid`` to the connector that faces it in
        the structure, or None if no module faces it."""
        facing = self.world.structure.facing(mid, physical)
        if facing is None or facing[0] not in self.world.robot.modules:
            return None
        a = self.connector_point(mid, physical)
        b = self.connector_point(*facing)
        return float(np.linalg.norm(a - b))

    def connector_point(self, mid: int, physical: int) -> np.ndarray:
        """Where a connector is in the world: on the shell, under the connector."""
        robot = self.world.robot
        mb, spec0 = robot.modules[mid], robot.specs[mid]
        side = g.physical_side(spec0, physical)
        state = pb.getLinkState(mb.body, mb.links[side], physicsClientId=self.world.client)
        m = np.array(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        frame = m @ np.array(mb.frames[side]) if side in mb.frames else m
        centre = np.array(state[4]) + m @ np.array(mb.offsets[side])
        return centre + frame @ np.array(connector_direction(spec0, physical)) * params.MODULE_RADIUS

    # ---- outside changes ---------------------------------------------------------------------
    def apply_outside(self, c: Any) -> None:
        """A ``vm.lattice.outside.OutsideChange`` whose time has come, said as the lattice world
        says it ("outside", or "outside_failed" with the reason)."""
        s = self.world.structure
        detail = {"change": c.text or c.describe()}
        if c.kind == "stop":
            ok = c.module in s.modules and self.stop(c.module)
            self.say(c.module, "outside" if ok else "outside_failed",
                     detail if ok else {**detail, "reason": f"no module {c.module}"})
            return
        if c.kind in ("jam", "fail"):  # the latch no longer moves, or once (changes.py)
            ok = c.module in s.modules and c.connector is not None
            if ok and c.kind == "jam":
                s.jammed = s.jammed | {(c.module, c.connector)}
            elif ok:
                s.failing = s.failing | {(c.module, c.connector)}
            self.say(c.module, "outside" if ok else "outside_failed",
                     detail if ok else {**detail, "reason": f"no module {c.module}"})
            return
        self.say(c.module, "outside", detail)

        def make(t: Structure) -> Any:
            return t.remove(c.module) if c.kind == "detach" else t.add(ModuleSpec(c.module, c.cell, c.axis,
                                                                                   c.mount))

        if self._beyond_links(c.module, "outside_failed", make, detail):
            return
        change = make(s)
        if not change.ok:
            self.say(c.module, "outside_failed", {**detail, "reason": change.reason})

    def detach(self, mid: int) -> int:
        """A person takes module ``mid`` away: its links open, it leaves the world."""
        if self._beyond_links(mid, "detach_failed", lambda t: t.remove(mid), {}):
            return 0
        return self._done(self.world.structure.remove(mid), "detach")

    def attach(self, spec: ModuleSpec) -> int:
        """A person puts a new module on a free cell against free connectors; they latch."""
        if self._beyond_links(spec.id, "attach_failed", lambda t: t.add(spec), {}):
            return 0
        return self._done(self.world.structure.add(spec), "attach")

    def _beyond_links(self, mid: int, kind: str, change: Callable[[Structure], Any],
                      detail: dict[str, Any]) -> bool:
        """Whether ``change`` (tried first on a copy of the structure) would leave a body PyBullet
        cannot build; if so it is said as ``kind`` with the cause "link_limit", and not made."""
        s = self.world.structure
        if len(s.modules) + 3 <= MAX_LINKS:  # n modules make at most n + 1 rigid parts in a body
            return False
        trial = s.copy()
        if not change(trial).ok:  # the structure refuses it, and says why, when it is made
            return False
        specs = {m: self.world.robot.specs.get(m, spec) for m, spec in trial.modules.items()}
        latches = [(k.a, k.a_physical, k.b, k.b_physical) for k in trial.links()]
        parts = largest_body(specs, latches, trial.entry)
        if parts + 1 <= MAX_LINKS:
            return False
        self.say(mid, kind, {**detail, "cause": "link_limit", "reason": (
            f"the physics world cannot build the changed structure: {parts} rigid parts in one body, "
            f"PyBullet takes at most {MAX_LINKS - 1}; use --world lattice")})
        return True

    def stop(self, mid: int) -> int:
        """Module ``mid`` stops for good: no more steps, packets or motion; its joint holds."""
        if mid not in self.world.hals or mid in self.world.stopped:
            return 0
        self.world.stopped.add(mid)
        self.world.joints[mid].stop()
        if mid in self.world.runtimes:
            self.world.runtimes[mid].halted = True
        return 1

    # ---- following the structure ------------------------------------------------------------
    def hear(self, change: Any) -> None:
        if change.op != "rotate":
            self.heard.append(change)
            self.busy = True
        if change.op == "remove":
            self.world.stopped.add(change.module)
            runtime = self.world.runtimes.get(change.module)
            if runtime is not None:
                runtime.halted = True
        self.relink()
        if change.op != "remove":  # a detach is said as the outside change that made it
            self.say(change.module, _KINDS[change.op], _detail(change))
        if change.parts:
            self.say(change.module, "split", {"parts": [sorted(p) for p in change.parts]})

    def relink(self) -> None:
        """IR links and attached connectors from the structure (a link needs a latch)."""
        s, w = self.world.structure, self.world
        w.network.refresh()
        for mid, hal in w.hals.items():
            hal._connected = s.connected_channels(mid) if mid in s.modules else frozenset()  # noqa: SLF001

    def tick(self) -> None:
        """After the modules' step: follow the turns under way, build the bodies again if the
        structure changed."""
        if self.turns:
            self._follow_turns()
        if self.heard:
            self.heard = []
            self._rebuild()
        self.busy = bool(self.turns)

    def _follow_turns(self) -> None:
        w = self.world
        for mid, (quarters, moving) in list(self.turns.items()):
            joint = w.joints[mid]
            if joint.stalled:
                del self.turns[mid]
                w.hals[mid].result = 0
                self.say(mid, "rotation_failed", {"quarters": quarters, "cause": "stalled", "reason": (
                    f"module {mid}'s joint stalled: its {params.JOINT_MAX_TORQUE:g} N·m could not turn "
                    f"the load")})
            elif not joint.is_turning():
                del self.turns[mid]
                miss = self.off_lattice(mid, quarters, moving)
                if miss:
                    w.hals[mid].result = 0
                    self.say(mid, "rotation_failed", {"quarters": quarters, "cause": "off_lattice",
                                                      "reason": miss})
                    continue
                change = w.structure.rotate(mid, quarters, moving=moving)
                w.hals[mid].result = self._done(change, "rotation")

    def off_lattice(self, mid: int, quarters: int, moving: int) -> str:
        """Why the modules a finished turn carried are not on the cells the structure says they
        reach ("" if they are), seen from the hemisphere of ``mid`` that stood still."""
        w, s = self.world, self.world.structure
        spec, spec0 = s.modules[mid], w.robot.specs[mid]
        states = hemisphere_states(w.robot, w.client)
        still = 1 - moving
        rot, origin = structure_frame(spec0, spec, still, states[node_of(spec0, still)])
        north, south = changes.sides(s, mid)
        p = placement(spec.axis, spec.mount)
        axis = (p[0][1], p[1][1], p[2][1])
        k = quarters if moving == 0 else -quarters
        for m in sorted(north if moving == 0 else south):
            d = tuple(a - b for a, b in zip(s.modules[m].position, spec.position, strict=True))
            want = np.array(spec.position) + np.array(quarter(axis, k, d))  # type: ignore[arg-type]
            got = cell_of(rot, origin, states[(m, g.PLUS)].centre)
            miss = float(np.linalg.norm(got - want)) * params.LATTICE_UNIT
            if miss > params.SNAP_DISTANCE:
                return (f"module {m} ended {miss * 100:.1f} cm from cell {tuple(int(c) for c in want)} "
                        f"(more than {params.SNAP_DISTANCE * 100:g} cm)")
        return ""

    def _rebuild(self) -> None:
        w, s = self.world, self.world.structure
        old = w.robot
        states = hemisphere_states(old, w.client)
        specs = {}
        for mid, spec in s.modules.items():
            if mid in old.specs:
                specs[mid] = old.specs[mid]
            else:  # attached from outside: created now, where its cell is in the world
                states.update(self._place(spec, states, specs))
                specs[mid] = spec
                self._new_module(mid)
        latches = [(k.a, k.a_physical, k.b, k.b_physical) for k in s.links()]
        w.robot = rebuild(old, specs, latches, s.entry, w.client, states, visuals=w.visuals)
        self.rebuilds += 1
        for mid, mb in w.robot.modules.items():
            w.joints[mid].rebind(mb.body, mb.joint)
        w.index_robot()
        w.update_joints()

    def _place(self, spec: ModuleSpec, states: dict, specs: dict[int, ModuleSpec]) -> dict:
        """World states of a new module's hemispheres: on its cell, in the structure frame that
        a latched neighbour already placed sees (``specs``: the modules placed so far, each as
        created), moving with that neighbour."""
        s = self.world.structure
        placed = [b for b, _ in s.neighbours(spec.id).values() if b in specs]
        near = min(placed) if placed else min(specs)  # attached in one tick to modules attached later
        spec0 = specs[near]
        ref = states[node_of(spec0, 0)]
        rot, origin = structure_frame(spec0, s.modules[near], 0, ref)
        centre = origin + rot @ (np.array(spec.position, dtype=float) * params.LATTICE_UNIT)
        velocity = ref.velocity + np.cross(ref.spin, centre - ref.centre)
        return {(spec.id, side): HemiState(centre, rot, velocity, ref.spin) for side in (g.PLUS, g.MINUS)}

    def _new_module(self, mid: int) -> None:
        from sim.hal import PhysicsHal

        w = self.world
        w.joints[mid] = PhysicsJoint(w.client, -1, None)
        w.hals[mid] = PhysicsHal(w, mid, w.joints[mid])
        w.add_runtime(mid)

    def say(self, mid: int, kind: str, detail: dict[str, Any]) -> None:
        w = self.world
        w.events.append((w.time, mid, kind, detail))
        if w.on_change is not None:
            w.on_change(w.time, mid, kind, detail)


# the event each change of the structure is reported as (the lattice world's words)
_KINDS = {"latch": "connect", "unlatch": "disconnect", "rotate": "rotation_end", "add": "attach",
          "remove": "detach"}
_HEMISPHERES = ("north", "south")


def _detail(change: Any) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if change.connector is not None:
        out["connector"] = change.connector
    if change.op == "rotate":
        out["quarters"] = change.quarters
        out["carried"] = list(change.moved)
    if change.link is not None:
        k = change.link
        out["link"] = [k.a, k.a_physical, k.b, k.b_physical]
    return out
