"""Sizes of the compiled fragments, with the roles and methods whose code each one holds.

One fragment may hold code of several roles and methods (the compiler shares code), so a method
is shown with every fragment that holds its code.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from rdcd_core.ide.analysis import Analysis

if TYPE_CHECKING:  # the compiler is imported only when sizes are asked for
    from rdcd_core.compiler.program import CompiledProgram


@dataclass(frozen=True)
class FragmentSize:
    name: str
    kind: str
    roles: tuple[str, ...]
    methods: tuple[str, ...]
    size: int  # program bytes

    def over(self, budget: int) -> bool:
        return self.size > budget


def fragment_sizes(analysis: Analysis) -> list[FragmentSize]:
    cached = analysis.cache.get("fragment_sizes")
    if cached is None:
        cached = analysis.cache["fragment_sizes"] = _fragment_sizes(analysis.compiled())
    return cached


def _fragment_sizes(compiled: CompiledProgram | None) -> list[FragmentSize]:
    if compiled is None:
        return []
    sizes = []
    for fragment in compiled.fragments:
        roles = tuple(fragment.roles)
        if fragment.role and fragment.role not in roles:
            roles += (fragment.role,)
        sizes.append(FragmentSize(fragment.name, fragment.kind, roles, tuple(fragment.methods),
                                  fragment.size))
    return sizes


def sizes_of_role(analysis: Analysis, roles: list[str]) -> list[FragmentSize]:
    """Fragments holding code of any of ``roles``."""
    wanted = set(roles)
    return [f for f in fragment_sizes(analysis) if wanted & set(f.roles)]


def sizes_of_method(analysis: Analysis, roles: list[str], method: str) -> list[FragmentSize]:
    return [f for f in sizes_of_role(analysis, roles) if method in f.methods]
