"""Document symbols (roles with their members, the deployment) and workspace symbol search."""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core.ide.analysis import Analysis
from rdcd_core.source import Span
from rdcd_core.syntax import ast


@dataclass
class Symbol:
    name: str
    kind: str  # role, mixin, state, constant, method, invariant, deployment
    detail: str
    span: Span
    selection: Span
    children: list[Symbol] = field(default_factory=list)


def _role_detail(role: ast.RoleDecl) -> str:
    words = ["abstract role" if role.is_abstract else "role"]
    if role.extends is not None:
        words.append(f"extends {role.extends.text}")
    if role.modifies is not None:
        words.append(f"modifies {role.modifies.text}")
    return " ".join(words)


def _member_symbols(text: str, role: ast.RoleDecl) -> list[Symbol]:
    result = []
    for member in role.members:
        if isinstance(member, ast.AbstractConstants):
            result += [Symbol(n.text, "constant", "abstract constant", member.span, n.span)
                       for n in member.names]
        elif isinstance(member, ast.ConstantDef):
            result.append(Symbol(member.name.text, "constant", "constant", member.span, member.name.span))
        elif isinstance(member, ast.StateDecl):
            result.append(_state_symbol(text, member, "role state"))
        elif isinstance(member, ast.MethodDecl):
            detail = " ".join(m.keyword for m in member.modifiers) or "method"
            if member.params:
                detail += f" ({', '.join(p.text for p in member.params)})"
            result.append(Symbol(member.name.text + "()", "method", detail, member.span, member.name.span))
    return result


def _state_symbol(text: str, decl: ast.StateDecl, kind: str) -> Symbol:
    initial = " ".join(text[decl.value.span.start:decl.value.span.end].split())  # as written, one line
    if len(initial) > 40:
        initial = initial[:39] + "…"
    return Symbol(decl.name.text, "state", f"{kind} := {initial}", decl.span, decl.name.span)


def document_symbols(analysis: Analysis) -> list[Symbol]:
    program = analysis.program
    if program is None:
        return []
    symbols = [_state_symbol(analysis.text, state, "module state")
               for state in program.states if state.name.text]
    for role in program.roles:
        if not role.name.text:
            continue
        kind = "mixin" if role.modifies is not None else "role"
        symbols.append(Symbol(role.name.text, kind, _role_detail(role), role.span, role.name.span,
                              _member_symbols(analysis.text, role)))
    if program.deployment is not None:
        deployment = program.deployment
        names = ", ".join(n.text for n in deployment.roles)
        symbols.append(Symbol("deployment", "deployment", names, deployment.span,
                              Span(deployment.span.start, deployment.span.start + len("deployment"))))
    symbols.sort(key=lambda symbol: symbol.span.start)  # module state may sit between roles
    return symbols


def workspace_symbols(documents: dict[str, Analysis], query: str) -> list[tuple[str, Symbol, str]]:
    """(uri, symbol, container) for every role and member whose name contains ``query``."""
    query = query.lower()
    found = []
    for uri, analysis in documents.items():
        for symbol in document_symbols(analysis):
            if query in symbol.name.lower():
                found.append((uri, symbol, ""))
            for child in symbol.children:
                if query in child.name.lower():
                    found.append((uri, child, symbol.name))
    return found
