"""Go to definition, find references, document highlight: one symbol identity for all three.

A constant or method is one symbol across the hierarchy: the abstract declaration in a super-role,
its definitions and overrides in sub-roles, and every use (``Role.cmd()`` calls included) share
the identity of the top-most role that declares the name.
"""

from __future__ import annotations

from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.states import assignment_starts, state_symbol
from rdcd_core.semantics.model import Model, Reference
from rdcd_core.source import Span

MEMBER_KINDS = ("constant", "method", "command")


def member_chain(model: Model, role: str) -> list[str]:
    """The roles whose members ``role`` sees: a mixin sees its own, then those of what it modifies."""
    symbol = model.roles.get(role)
    if symbol is not None and symbol.is_mixin and symbol.modifies:
        return [role] + model.ancestors(symbol.modifies)
    return model.ancestors(role)


def _has_member(model: Model, role: str, name: str, constant: bool) -> bool:
    symbol = model.roles.get(role)
    if symbol is None:
        return False
    return name in (symbol.constants if constant else symbol.methods)


def split_target(target: str) -> tuple[str, str]:
    role, _, name = target.partition(".")
    return role, name


def symbol_key(model: Model, ref: Reference) -> tuple[str, str]:
    if ref.kind not in MEMBER_KINDS:
        return ref.kind, ref.target
    role, name = split_target(ref.target)
    constant = ref.kind == "constant"
    root = role
    for ancestor in member_chain(model, role):
        if _has_member(model, ancestor, name, constant):
            root = ancestor
    return ("constant" if constant else "method"), f"{root}.{name}"


def occurrences(analysis: Analysis, ref: Reference) -> list[Reference]:
    model = analysis.model
    if model is None:
        return []
    key = symbol_key(model, ref)
    cache: dict[tuple[str, str], tuple[str, str]] = {}
    found = []
    for other in analysis.references():
        if other.name.text != ref.name.text:
            continue
        probe = (other.kind, other.target)
        if probe not in cache:
            cache[probe] = symbol_key(model, other)
        if cache[probe] == key:
            found.append(other)
    return found


def definition(analysis: Analysis, offset: int) -> list[Span]:
    ref = analysis.reference_at(offset)
    model = analysis.model
    if ref is None or model is None:
        return []
    if ref.kind == "role":
        symbol = model.roles.get(ref.target)
        return [symbol.decl.name.span] if symbol is not None and symbol.decl is not None else []
    if ref.kind in MEMBER_KINDS:
        role, name = split_target(ref.target)
        symbol = model.roles.get(role)
        if symbol is None:
            return []
        if ref.kind == "constant" and name in symbol.constants:
            return [symbol.constants[name].declaration.span]
        if ref.kind != "constant" and name in symbol.methods:
            return [symbol.methods[name].decl.name.span]
        # fall back to any declaration of the same symbol
        return [r.name.span for r in occurrences(analysis, ref) if r.is_definition][:1]
    if ref.kind == "state":
        state = state_symbol(model, ref.target)
        return [state.decl.name.span] if state is not None else []
    if ref.kind == "parameter":
        return [r.name.span for r in occurrences(analysis, ref) if r.is_definition][:1]
    return []


def references(analysis: Analysis, offset: int, include_declaration: bool = True) -> list[Span]:
    ref = analysis.reference_at(offset)
    if ref is None:
        return []
    return [r.name.span for r in occurrences(analysis, ref) if include_declaration or not r.is_definition]


def highlights(analysis: Analysis, offset: int) -> list[tuple[Span, bool]]:
    """Every occurrence in this document, with True for declarations and assignments (writes)."""
    ref = analysis.reference_at(offset)
    if ref is None:
        return []
    writes = assignment_starts(analysis) if ref.kind == "state" else set()
    return [(r.name.span, r.is_definition or r.name.span.start in writes) for r in occurrences(analysis, ref)]
