"""State and parameters for the IDE features: symbols from reference targets, and where states
are assigned (for hover, highlights and semantic tokens)."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.semantics.model import Model, StateSymbol
from rdcd_core.syntax import ast


@dataclass(frozen=True)
class ParameterInfo:
    role: str  # the role that declares the method
    method: ast.MethodDecl
    name: ast.Name  # the declaration
    index: int


def state_symbol(model: Model, target: str) -> StateSymbol | None:
    """The state a ``state`` reference's target names: ``name`` (module) or ``Role.name``."""
    role, dot, name = target.partition(".")
    if not dot:
        return model.states.get(target)
    symbol = model.roles.get(role)
    return symbol.states.get(name) if symbol is not None else None


def method_decl(model: Model, role: str, name: str) -> ast.MethodDecl | None:
    """The method ``name`` as written in role ``role`` (its own declaration, not an inherited one)."""
    symbol = model.roles.get(role)
    if symbol is None or symbol.decl is None:
        return None
    for member in symbol.decl.members:
        if isinstance(member, ast.MethodDecl) and member.name.text == name:
            return member
    return None


def parameter_info(model: Model, target: str) -> ParameterInfo | None:
    """The parameter a ``parameter`` reference's target (``Role.method.name``) names."""
    parts = target.split(".")
    if len(parts) != 3:
        return None
    role, method_name, name = parts
    method = method_decl(model, role, method_name)
    if method is None:
        return None
    for index, param in enumerate(method.params):
        if param.text == name:
            return ParameterInfo(role, method, param, index)
    return None


def assignment_starts(analysis: Analysis) -> set[int]:
    """Start offsets of every assigned name (``s := …;``): the writes of states."""
    cached = analysis.cache.get("assignment_starts")
    if cached is None:
        cached = set()
        model = analysis.model
        # a program without state (every program before state existed) costs no walk
        if analysis.program is not None and (model is None or model.all_states()):
            for node in ast.walk(analysis.program):
                if isinstance(node, ast.AssignStmt):
                    cached.add(node.name.span.start)
        analysis.cache["assignment_starts"] = cached
    return cached


def assigning_methods(analysis: Analysis, target: str) -> list[str]:
    """``Role.method`` of every method that assigns the state ``target``, in text order."""
    writes = assignment_starts(analysis)
    spans = {r.name.span.start for r in analysis.references()
             if r.kind == "state" and r.target == target and r.name.span.start in writes}
    program = analysis.program
    if not spans or program is None:
        return []
    found: list[str] = []
    for role in program.roles:
        for member in role.members:
            if isinstance(member, ast.MethodDecl) and any(
                    member.span.start <= s < member.span.end for s in spans):
                found.append(f"{role.name.text}.{member.name.text}")
    return found


def signature_text(method: ast.MethodDecl) -> str:
    return f"{method.name.text}({', '.join(p.text for p in method.params)})"
