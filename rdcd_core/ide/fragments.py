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


def sizes_for_role(analysis: Analysis, name: str) -> list[FragmentSize]:
    """Fragments holding code of role ``name``'s concrete subroles (of ``name`` itself when it has
    none): ``sizes_of_role(analysis, model.concrete_subroles(name) or [name])``, from an index
    made once per analysis, so that hints for every role of a document stay linear."""
    by_ancestor, covered, direct = _role_index(analysis)
    return by_ancestor.get(name, []) if name in covered else direct.get(name, [])


def sizes_for_method(analysis: Analysis, role: str, method: str) -> list[FragmentSize]:
    return [f for f in sizes_for_role(analysis, role) if method in f.methods]


Index = tuple[dict[str, list[FragmentSize]], set[str], dict[str, list[FragmentSize]]]


def _role_index(analysis: Analysis) -> Index:
    cached = analysis.cache.get("role_fragments")
    if cached is None:
        cached = analysis.cache["role_fragments"] = _make_role_index(analysis)
    return cached


def _make_role_index(analysis: Analysis) -> Index:
    from rdcd_core.semantics.model import RoleKind

    model = analysis.model
    roles = model.roles if model is not None else {}
    concrete = {name for name, symbol in roles.items() if symbol.kind is RoleKind.CONCRETE}
    covered: set[str] = set()  # the roles that have a concrete subrole (themselves included)
    for name in concrete:
        current: str | None = name
        while current is not None and current in roles and current not in covered:
            covered.add(current)  # above a covered role every ancestor is covered: stop there
            current = roles[current].parent
    by_ancestor: dict[str, list[FragmentSize]] = {}
    direct: dict[str, list[FragmentSize]] = {}
    for fragment in fragment_sizes(analysis):
        above: set[str] = set()
        for role in dict.fromkeys(fragment.roles):
            direct.setdefault(role, []).append(fragment)
            if role in concrete:
                above.update(model.ancestors(role))  # type: ignore[union-attr]
        for ancestor in above:
            by_ancestor.setdefault(ancestor, []).append(fragment)
    return by_ancestor, covered, direct
