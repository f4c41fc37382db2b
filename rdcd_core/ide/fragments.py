"""Sizes of the compiled fragments, with the roles and methods whose code each one holds.

One fragment may hold code of several roles and methods (the compiler shares code), so a method
is shown with every fragment that holds its code.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from rdcd_core.ide.analysis import Analysis

DEFAULT_PROGRAM_BUDGET = 43


@dataclass(frozen=True)
class FragmentSize:
    name: str
    kind: str
    roles: tuple[str, ...]
    methods: tuple[str, ...]
    size: int  # program bytes

    def over(self, budget: int) -> bool:
        return self.size > budget


def program_budget(compiled: Any) -> int:
    value = getattr(compiled, "program_budget", None)
    return value if isinstance(value, int) else DEFAULT_PROGRAM_BUDGET


def fragment_sizes(analysis: Analysis) -> list[FragmentSize]:
    cached = analysis.cache.get("fragment_sizes")
    if cached is None:
        cached = analysis.cache["fragment_sizes"] = _fragment_sizes(analysis)
    return cached


def _fragment_sizes(analysis: Analysis) -> list[FragmentSize]:
    compiled = analysis.compiled()
    if compiled is None:
        return []
    sizes = []
    for fragment in getattr(compiled, "fragments", ()) or ():
        roles = tuple(getattr(fragment, "roles", ()) or ())
        role = getattr(fragment, "role", None)
        if role and role not in roles:
            roles += (role,)
        sizes.append(FragmentSize(
            name=str(getattr(fragment, "name", "")),
            kind=str(getattr(fragment, "kind", "")),
            roles=roles,
            methods=tuple(getattr(fragment, "methods", ()) or ()),
            size=len(getattr(fragment, "code", b"") or b""),
        ))
    return sizes


def sizes_of_role(analysis: Analysis, roles: list[str]) -> list[FragmentSize]:
    """Fragments holding code of any of ``roles``."""
    wanted = set(roles)
    return [f for f in fragment_sizes(analysis) if wanted & set(f.roles)]


def sizes_of_method(analysis: Analysis, roles: list[str], method: str) -> list[FragmentSize]:
    return [f for f in sizes_of_role(analysis, roles) if method in f.methods]
