"""Success criteria on the final state of a run: ``[success.state]`` and ``[success.held_by]``.

    [success.state]
    hops = "hop_distance"            # every module: its distance in hops from the entry module
    size = { entry = "modules" }     # the entry module only: the number of modules
    lowest = "lowest_z"              # every module: the smallest z of the structure

    [success.held_by]
    Bottom = "lowest"                # exactly the modules with the smallest z end in role Bottom

An expected value is an integer or one of ``VALUES``; a plain value checks every module, a table
``{ entry = V }`` the entry module only (``{ all = V }`` is every module, spelled out). A module that
does not have the state at the end (a role state of a role it does not play) fails the check. A
role is held by the modules whose final role has that name; ``HOLDERS`` say which modules those
must be.

A row keeps the facts the checks need (``final``: per module its z, hop distance, final role and
final state), not the verdict, so changing the criteria re-judges the runs without running them.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any

from vm.lattice.structure import Structure

VALUES = ("hop_distance", "modules", "z", "lowest_z")
SCOPES = ("all", "entry")
HOLDERS = ("lowest", "entry", "all", "none")


@dataclass(frozen=True)
class StateCheck:
    state: str
    expected: int | str  # an integer or a name in VALUES
    scope: str = "all"  # a name in SCOPES

    def describe(self) -> str:
        who = "the entry module's" if self.scope == "entry" else "every module's"
        return f"{who} {self.state} == {self.expected}"


@dataclass(frozen=True)
class HeldBy:
    role: str
    holders: str  # a name in HOLDERS

    def describe(self) -> str:
        who = {"lowest": "exactly the lowest modules", "entry": "exactly the entry module",
               "all": "every module", "none": "no module"}[self.holders]
        return f"{self.role} held by {who}"


def parse_state(table: Any, states: set[str] | None) -> tuple[tuple[StateCheck, ...], str | None]:
    """The checks of ``[success.state]``, or the problem (``key: message``) with it. ``states``: the
    program's state names, when known, to refuse a name it does not have."""
    if not isinstance(table, dict):
        return (), "success.state: must be a table of state = expected value"
    checks = []
    for name, raw in table.items():
        key = f"success.state.{name}"
        if states is not None and name not in states:
            known = ", ".join(sorted(states)) or "none"
            return (), f"{key}: the program has no state {name!r} (its states: {known})"
        scope, value = "all", raw
        if isinstance(raw, dict):
            if len(raw) != 1 or next(iter(raw)) not in SCOPES:
                return (), f"{key}: a table must be {{ entry = V }} or {{ all = V }}"
            scope, value = next(iter(raw.items()))
        if isinstance(value, bool) or not isinstance(value, (int, str)) or (
                isinstance(value, str) and value not in VALUES):
            return (), f"{key}: must be an integer or one of {', '.join(VALUES)}"
        if isinstance(value, int) and not -128 <= value <= 127:
            return (), f"{key}: {value} is not a value a state can hold (-128..127)"
        checks.append(StateCheck(name, value, scope))
    return tuple(checks), None


def parse_held_by(table: Any, roles: set[str] | None) -> tuple[tuple[HeldBy, ...], str | None]:
    if not isinstance(table, dict):
        return (), "success.held_by: must be a table of role = which modules"
    checks = []
    for role, holders in table.items():
        key = f"success.held_by.{role}"
        if roles is not None and role not in roles:
            return (), f"{key}: the program has no role {role!r} (its roles: {', '.join(sorted(roles))})"
        if holders not in HOLDERS:
            return (), f"{key}: must be one of {', '.join(HOLDERS)}"
        checks.append(HeldBy(role, holders))
    return tuple(checks), None


def hop_distances(structure: Structure) -> dict[int, int]:
    """Shortest path lengths from the entry module in the connection graph (unreached: absent)."""
    distances = {structure.entry: 0}
    todo = deque([structure.entry])
    while todo:
        current = todo.popleft()
        for other, _ in structure.neighbours(current).values():
            if other not in distances:
                distances[other] = distances[current] + 1
                todo.append(other)
    return distances


def facts(report: dict[str, Any], structure: Structure) -> dict[str, Any]:
    """What a row keeps for the checks: the entry module, and per module [id, z, hops, role, state]."""
    hops = hop_distances(structure)
    return {"entry": structure.entry,
            "modules": [[m["id"], m["lattice"][2], hops.get(m["id"]), m["final_role"],
                         m.get("final_state", {})] for m in report["modules"]]}


def _expected(check: StateCheck, module: list[Any], final: dict[str, Any]) -> int | None:
    if isinstance(check.expected, int):
        return check.expected
    mid, z, hops, _, _ = module
    return {"hop_distance": hops, "modules": len(final["modules"]), "z": z,
            "lowest_z": min(m[1] for m in final["modules"])}[check.expected]


def holds(final: dict[str, Any] | None, state: tuple[StateCheck, ...], held_by: tuple[HeldBy, ...]) -> bool:
    """Whether a row's facts pass every check (no facts: an old row, or none needed)."""
    if not state and not held_by:
        return True
    if not final or not final.get("modules"):
        return False
    modules = final["modules"]
    for check in state:
        chosen = [m for m in modules if check.scope == "all" or m[0] == final["entry"]]
        if not chosen:
            return False
        for module in chosen:
            value = module[4].get(check.state)
            if value is None or value != _expected(check, module, final):
                return False
    lowest = min(m[1] for m in modules)
    for rule in held_by:
        holders = {m[0] for m in modules if m[3] == rule.role}
        wanted = {"lowest": {m[0] for m in modules if m[1] == lowest}, "entry": {final["entry"]},
                  "all": {m[0] for m in modules}, "none": set()}[rule.holders]
        if holders != wanted:
            return False
    return True
