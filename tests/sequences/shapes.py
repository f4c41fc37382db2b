"""The shape of a structure, for comparing the end of a run with the checker's: each module's cell
and the links (module, physical connector, module, physical connector), from a report or from a
lattice ``Structure``."""

from __future__ import annotations

from typing import Any


def shape(report: dict) -> tuple[dict, set]:
    cells = {m["id"]: tuple(m["final_lattice"]) for m in report["modules"]}
    return cells, {tuple(c) for c in report["connections"]}


def structure_shape(structure: Any) -> tuple[dict, set]:
    cells = {m: tuple(s.position) for m, s in structure.modules.items()}
    return cells, {(k.a, k.a_physical, k.b, k.b_physical) for k in structure.links()}
