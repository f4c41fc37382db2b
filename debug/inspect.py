"""What the debugger shows of a module: its scopes (plain nested dicts and lists of values, turned
into DAP variables by ``debug.session``), the names conditions and ``evaluate`` read, and its
full state for comparisons (going forward again after going back must give the same states).

Reading never changes anything: no runtime method with an effect is called.
"""

from __future__ import annotations

import math
from typing import Any

from debug.code import CodeIndex
from sim.state_report import plays
from vm.interpreter import Frame
from vm.isa.opcodes import PUBLISHED_SLOTS, USER_COMMAND_BASE
from vm.lattice.structure import AXIS_NAMES
from vm.packets import ACK, COMMAND, NOTIFY, PROGRAM

PACKET_KINDS = {PROGRAM: "program", COMMAND: "command", NOTIFY: "notify", ACK: "ack"}
SENSORS = 8


def role_name(runtime: Any) -> str:
    return runtime.roles.name(runtime.role) if runtime.role else "none"


def thread_name(runtime: Any, structure: Any) -> str:
    position = structure.modules[runtime.module_id].position
    return f"module {runtime.module_id} {role_name(runtime)} ({', '.join(str(v) for v in position)})"


def _axis(axis: int | None) -> str:
    return AXIS_NAMES.get(axis, str(axis)) if axis is not None else "unknown"


def _joint(runtime: Any) -> tuple[float, float]:
    """(angle in degrees, speed in degrees per second) of the module's joint."""
    hal = runtime.hal
    joint = getattr(hal, "joint", None)
    angle = hal.joint_angle_deg() if joint is not None else 0.0
    if joint is None:
        return angle, 0.0
    if hasattr(joint, "speed_deg_s"):  # the lattice joint: degrees per second
        return angle, float(getattr(joint, "_velocity", 0.0))
    return angle, math.degrees(getattr(joint, "velocity", 0.0))  # PyBullet's: radians per second


def names(runtime: Any, frame: Frame | None, run: Any) -> dict[str, Any]:
    """The names a condition, a log message or ``evaluate`` may read."""
    angle, speed = _joint(runtime)
    position = runtime.position or (None, None, None)
    out: dict[str, Any] = {
        "module": runtime.module_id, "role": role_name(runtime), "role_id": runtime.role,
        "x": position[0], "y": position[1], "z": position[2], "axis": _axis(runtime.axis),
        "led": runtime.led, "angle": round(angle, 3), "speed": round(speed, 3),
        "time": round(run.time, 6) if run is not None else 0.0, "halted": runtime.halted,
        "errors": len(runtime.errors), "programs_run": runtime.programs_run, "runs": runtime.runs,
        "lattice_x": None, "lattice_y": None, "lattice_z": None,
    }
    spec = run.structure.modules.get(runtime.module_id) if run is not None else None
    if spec is not None:  # a detached module has no cell
        out["lattice_x"], out["lattice_y"], out["lattice_z"] = spec.position
    for k in range(SENSORS):
        out[f"sensor{k}"] = _sensor(runtime, k)
    if frame is not None:
        out.update({"pc": frame.pc, "arg": frame.arg, "depth": len(frame.stack),
                    "top": frame.stack[-1] if frame.stack else None})
    for name, value in state_values(runtime, getattr(run, "program", None)).items():
        out.setdefault(name, value)
    return out


def _sensor(runtime: Any, k: int) -> bool | None:
    """What sensor ``k`` sees; None for a physics sensor that nothing reads, which the world does
    not sample (asking the hal would start sampling it: a change to the world)."""
    sensors = getattr(getattr(runtime.hal, "world", None), "sensors", None)
    if sensors is not None and hasattr(sensors, "watched"):
        key = (runtime.module_id, k)
        return sensors.values.get(key, False) if key in sensors.watched else None
    try:
        return bool(runtime.hal.proximity(k))
    except (IndexError, KeyError, ValueError, AttributeError):
        return None


def state_values(runtime: Any, program: Any = None) -> dict[str, Any]:
    """The module's state by name (the compiled program's layout): module state always, a role
    state only while the module plays its role (its byte means nothing in another role); without
    a layout, the raw bytes."""
    state = getattr(runtime, "state", None)
    if state is None:
        return {}
    entries = getattr(program, "states", None)
    if entries is not None and isinstance(state, (list, tuple)):
        role = runtime.roles.name(runtime.role) if runtime.role else None
        return {e.name: state[e.index] for e in entries if e.index < len(state) and plays(e, role)}
    if isinstance(state, dict):
        return {str(k): v for k, v in state.items()}
    if isinstance(state, (list, tuple)):
        return {f"state{i}": v for i, v in enumerate(state)}
    values = getattr(state, "__dict__", None)
    return {k: v for k, v in values.items() if not k.startswith("_")} if values else {"state": state}


class Inspector:
    def __init__(self, code: CodeIndex) -> None:
        self.code = code

    def where(self, code: bytes | None, pc: int | None) -> str:
        if code is None or pc is None:
            return "?"
        located = self.code.locate(code, pc)
        if located is None:
            return f"pc {pc} (code not in the program)"
        index, offset = located
        line = self.code.line(index, offset)
        return f"{self.code.fragments[index].name}+{offset}" + (f" (line {line})" if line else "")

    def scopes(self, runtime: Any, frame: Frame | None, run: Any) -> list[tuple[str, Any, bool]]:
        """(name, content, expensive) of each scope of a module (``frame``: the frame shown)."""
        out: list[tuple[str, Any, bool]] = [("Module", self.module(runtime, run), False)]
        if frame is not None:
            out.append(("Operand stack", self.stack(frame), False))
        state = state_values(runtime, self.code.program)
        if state or hasattr(runtime, "state"):
            out.append(("State", state, False))
        out += [("Event handlers", self.handlers(runtime), False),
                ("Stored programs", self.programs(runtime), False),
                ("Task queue", self.tasks(runtime), False),
                ("Command table", self.commands(runtime), False),
                ("Neighbours", self.neighbours(runtime, run), False),
                ("Packets in flight", self.packets(runtime, run), False)]
        return out

    def module(self, runtime: Any, run: Any) -> dict[str, Any]:
        angle, speed = _joint(runtime)
        spec = run.structure.modules.get(runtime.module_id)  # None: detached from outside
        return {
            "module": runtime.module_id, "role": role_name(runtime), "role id": runtime.role,
            "lattice position": list(spec.position) if spec else "detached",
            "lattice axis": _axis(spec.axis) if spec else None,
            "learned coordinates": list(runtime.position) if runtime.position else None,
            "learned axis": _axis(runtime.axis),
            "mapping (virtual→physical)": list(runtime.mapping) if runtime.mapping else None,
            "joint angle (°)": round(angle, 3), "joint speed (°/s)": round(speed, 3),
            "LED": runtime.led,
            "connections": self.connections(runtime, run),
            "sensors": {str(k): _sensor(runtime, k) for k in range(SENSORS)},
            "halted": runtime.halted, "programs run": runtime.programs_run, "runs": runtime.runs,
            "errors": [f"t={t:.3f} s: {m}" for t, m in runtime.errors[-20:]],
            "role history": [f"t={t:.3f} s: {runtime.roles.name(r) if r else 'none'}"
                             for t, r in runtime.role_history[-20:]],
            "time (s)": round(run.time, 6),
        }

    def stack(self, frame: Frame) -> dict[str, Any]:
        out: dict[str, Any] = {"pc": frame.pc, "argument": frame.arg, "depth": len(frame.stack)}
        for i, value in enumerate(reversed(frame.stack)):
            out[f"[{i}]" + (" top" if i == 0 else "")] = value
        return out

    def _slot(self, slot: Any) -> dict[str, Any]:
        return {"id": slot.ident, "kind": slot.kind, "bytes": len(slot.code), "started": slot.started,
                "at": self.where(slot.code, 0), "came in on connector": slot.in_physical}

    def handlers(self, runtime: Any) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for k, vector in enumerate(runtime.store.vectors):
            if vector is not None:
                out[f"event {k}"] = {"enabled": vector.enabled, "armed": vector.armed,
                                     "sensor sees": _sensor(runtime, k), **self._slot(vector.slot)}
        return out

    def programs(self, runtime: Any) -> dict[str, Any]:
        return {f"slot {i}": self._slot(slot) for i, slot in enumerate(runtime.store.slots)}

    def tasks(self, runtime: Any) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for i, task in enumerate(runtime.store.tasks):
            item: dict[str, Any] = {"argument": task.arg}
            if task.slot is None:
                item["command"] = task.command
            else:
                item.update(self._slot(task.slot))
            if task.frame is not None:
                item["pc"] = task.frame.pc
                item["at"] = self.where(task.frame.code, task.frame.pc)
                item["stack"] = list(task.frame.stack)
            if task.wake_time is not None:
                item["wakes at (s)"] = round(task.wake_time, 6)
            if task.wake_turns is not None:
                item["wakes at joint turn"] = round(task.wake_turns, 3)
            out[f"task {i}"] = item
        return out

    def commands(self, runtime: Any) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for role, entries in sorted(runtime.store.commands.items()):
            name = runtime.roles.name(role) if role else "none"
            out[name] = {f"command {USER_COMMAND_BASE + k}": (self.where(s.code, 0) if s else None)
                         for k, s in enumerate(entries)}
        return out

    def neighbours(self, runtime: Any, run: Any) -> dict[str, Any]:
        """Per virtual connector: the role the neighbour last notified and the published values it
        last sent, by state name (what the module *heard*, which is what its aggregates read; a
        gradient is debugged by comparing these with the neighbour's own State), and which module
        is attached there now."""
        mapping = runtime.mapping
        attached = (run.structure.neighbours(runtime.module_id)
                    if run is not None and runtime.module_id in run.structure.modules else {})
        published = [e for e in getattr(getattr(run, "program", None), "states", None) or ()
                     if e.index < PUBLISHED_SLOTS]
        cache = getattr(runtime, "neighbour_cache", None)
        out: dict[str, Any] = {}
        for v, r in enumerate(runtime.neighbour_roles):
            item: dict[str, Any] = {"role": runtime.roles.name(r) if r else "none"}
            physical = mapping[v] if mapping else None
            if physical is not None:
                item["physical connector"] = physical
                peer = attached.get(physical)
                item["module attached"] = f"module {peer[0]} connector {peer[1]}" if peer else None
            heard = cache[v] if cache is not None else None
            if isinstance(heard, (list, tuple)):  # the firmware profile caches roles only
                if published:
                    item["heard"] = {e.name: heard[e.index] for e in published}
                elif any(value is not None for value in heard):
                    item["heard"] = {f"state{i}": value for i, value in enumerate(heard)
                                     if value is not None}
            out[f"virtual connector {v}"] = item
        return out

    def connections(self, runtime: Any, run: Any) -> list[str]:
        """The module's latched connections now: its physical connector, the module and connector
        on the other side."""
        if run is None or runtime.module_id not in run.structure.modules:  # detached: none
            return []
        return [f"connector {c} ↔ module {peer} connector {pc}"
                for c, (peer, pc) in sorted(run.structure.neighbours(runtime.module_id).items())]

    def packets(self, runtime: Any, run: Any) -> dict[str, Any]:
        mid = runtime.module_id
        network = run.world.network
        structure = run.structure
        incoming = []
        for item in sorted(network._queue):  # noqa: SLF001 - read only
            if item.target == mid:
                peer = structure.neighbours(mid).get(item.physical)
                incoming.append({"from module": peer[0] if peer else None, "connector": item.physical,
                                 "kind": _kind(item.packet), "bytes": len(item.packet),
                                 "due (s)": round(item.due, 6)})
        outgoing = []
        for item in sorted(network._queue):  # noqa: SLF001
            peer = structure.neighbours(item.target).get(item.physical)
            if peer is not None and peer[0] == mid:
                outgoing.append({"to module": item.target, "kind": _kind(item.packet),
                                 "bytes": len(item.packet), "due (s)": round(item.due, 6)})
        waiting = [{"connector": p.channel, "kind": _kind(p.packet), "tries": p.tries,
                    "next try (s)": round(p.due, 6)} for p in runtime.link.outbox]
        return {"to this module": incoming, "from this module": outgoing,
                "waiting for acknowledgement": waiting}

    def full_state(self, runtime: Any, run: Any, frame: Frame | None = None) -> dict[str, Any]:
        """Everything shown of a module, for comparisons between two visits of one moment."""
        state = {name: content for name, content, _ in self.scopes(runtime, frame, run)}
        state["rng"] = runtime.rng.getstate()
        state["seen programs"] = sorted((i, c.hex()) for i, c in runtime._seen_programs)  # noqa: SLF001
        return state


def _kind(packet: bytes) -> str:
    return PACKET_KINDS.get(packet[0], "?") if packet else "empty"
