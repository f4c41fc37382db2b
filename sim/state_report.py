"""The state part of the simulation report: each module's final values, its history of changes,
and the values that never settled.

Names come from the compiler's layout of the state memory (``CompiledProgram.states``: a name per
byte of ``ModuleRuntime.state``); the runtime logs every change as (t, index, value).

- ``final_state``: ``{"name": value}`` of every module state, and of every role state of the role
  the module plays at the end (its own role or one it extends). A role state of another role is
  left out: its byte holds a value of a role the module no longer plays, which means nothing.
- ``state_history``: ``[[t, "name", value], ...]``, every change in time order (writes in one
  instant are one change, or none when they give the value back: vm/runtime.py), the last
  ``MAX_STATE_HISTORY`` of them (``state_history_omitted`` counts the earlier ones left out). A role
  state changes only while its role is played; taking the role sets it back to its initial value,
  which is a change like any other.
- A value has *not settled* when it still changed during the last part of the run: the last 10 %
  of the duration, and at least the last second (``settle_window``).
"""

from __future__ import annotations

from typing import Any

from rdcd_core.compiler.program import CompiledProgram, StateEntry

MAX_STATE_HISTORY = 500  # changes kept per module in the report (the runtime keeps 10,000)
SETTLE_FRACTION = 0.1
SETTLE_MIN_S = 1.0


def settle_window(duration: float) -> float:
    """Seconds at the end of a run in which a change means the value has not settled."""
    return min(duration, max(SETTLE_MIN_S, SETTLE_FRACTION * duration))


def _by_index(program: CompiledProgram) -> dict[int, StateEntry]:
    return {s.index: s for s in program.states}


def plays(entry: StateEntry, role: str | None) -> bool:
    """Whether a module whose role is ``role`` has ``entry``: module state always, role state only
    in its role or a role extending it."""
    return entry.owner is None or (role is not None and role in (entry.roles or (entry.owner,)))


def module_fields(program: CompiledProgram, runtime: Any, final_role: str | None) -> dict[str, Any]:
    """``final_state``, ``state_history`` and ``state_history_omitted`` of one module."""
    entries = _by_index(program)
    state = getattr(runtime, "state", None) or []
    final = {e.name: int(state[e.index]) for e in program.states
             if e.index < len(state) and plays(e, final_role)}
    changes = [(t, entries[i].name, v) for t, i, v in getattr(runtime, "state_history", []) if i in entries]
    kept = changes[-MAX_STATE_HISTORY:]
    return {"final_state": final,
            "state_history": [[round(t, 3), name, int(v)] for t, name, v in kept],
            "state_history_omitted": len(changes) - len(kept)}


def last_changes(module: dict[str, Any]) -> dict[str, float]:
    """The time of the last change of each state of a report's module entry."""
    last: dict[str, float] = {}
    for t, name, _ in module.get("state_history", []):
        last[name] = t
    return last


def unsettled(modules: list[dict[str, Any]], duration: float) -> list[dict[str, Any]]:
    """The states that still changed in the run's last ``settle_window``: for each, the modules
    where it did and the time of its last change, in the order of the state's first appearance."""
    since = duration - settle_window(duration)
    found: dict[str, dict[str, Any]] = {}
    for module in modules:
        for name, t in last_changes(module).items():
            if t > since + 1e-9:
                entry = found.setdefault(name, {"state": name, "modules": [], "last_change_s": t})
                entry["modules"].append(module["id"])
                entry["last_change_s"] = max(entry["last_change_s"], t)
    return list(found.values())


def report_fields(program: CompiledProgram, modules: list[dict[str, Any]], duration: float) -> dict[str, Any]:
    """The report's top-level state fields, from its modules (already carrying ``module_fields``)."""
    return {
        "states": [{"name": s.name, "index": s.index, "initial": s.initial, "owner": s.owner,
                    "published": s.published, "roles": list(s.roles)} for s in program.states],
        "settle_window_s": round(settle_window(duration), 3),
        "unsettled": unsettled(modules, duration),
    }


MAX_MODULES_NAMED = 8


def summary_lines(report: dict[str, Any]) -> list[str]:
    """What the text summary says about state: when each one settled, or where it never did."""
    states = report.get("states") or []
    if not states:
        return []
    lines = []
    open_states = {u["state"]: u for u in report.get("unsettled", [])}
    for u in open_states.values():
        ids = u["modules"]
        named = ", ".join(map(str, ids[:MAX_MODULES_NAMED])) + (
            f" and {len(ids) - MAX_MODULES_NAMED} more" if len(ids) > MAX_MODULES_NAMED else "")
        lines.append(f"state '{u['state']}' still changing on module{'s' if len(ids) > 1 else ''} {named} "
                     f"at the end (changed in the last {report['settle_window_s']:g} s; not settled)")
    settled = []
    for name in dict.fromkeys(s["name"] for s in states):
        if name in open_states:
            continue
        times = [last_changes(m).get(name) for m in report["modules"]]
        times = [t for t in times if t is not None]
        settled.append(f"{name} at {max(times):.2f} s" if times else f"{name} never changed")
    if settled:
        lines.append("state settled: " + ", ".join(settled))
    return lines
