"""Inlay hints: beside each role and method, the bytes of the fragments compiled from it."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.fragments import FragmentSize, sizes_for_method, sizes_for_role
from rdcd_core.syntax import ast


@dataclass(frozen=True)
class InlayHint:
    offset: int
    label: str
    tooltip: str
    over_budget: bool


def label(sizes: list[FragmentSize], budget: int) -> tuple[str, str, bool]:
    over = any(f.over(budget) for f in sizes)
    label = " + ".join(f"{f.size} B" for f in sizes)
    if over:
        label += f" ⚠ over {budget} B"
    listed = "; ".join(f"{f.name}: {f.size} B" + (" (over budget)" if f.over(budget) else "") for f in sizes)
    tooltip = f"compiled fragments, program bytes (packet budget {budget} B): {listed}"
    return label, tooltip, over


def fragment_hints(analysis: Analysis, start: int = 0, end: int | None = None) -> list[InlayHint]:
    program, model = analysis.program, analysis.model
    if program is None or model is None or analysis.compiled() is None:
        return []
    end = len(analysis.text) if end is None else end
    budget = analysis.compiled().program_budget
    hints = []
    for role in program.roles:
        if role.span.end < start or role.span.start > end or model.role_of(role) is None:
            continue
        own = sizes_for_role(analysis, role.name.text)
        if own and start <= role.header_span.end <= end:
            text, tooltip, over = label(own, budget)
            hints.append(InlayHint(role.header_span.end, text, tooltip, over))
        for member in role.members:
            if not isinstance(member, ast.MethodDecl) or not start <= member.span.start <= end:
                continue
            found = sizes_for_method(analysis, role.name.text, member.name.text)
            if found:
                text, tooltip, over = label(found, budget)
                close = analysis.text.find(")", member.name.span.end, member.span.end)
                position = close + 1 if close >= 0 else member.name.span.end
                hints.append(InlayHint(position, text, tooltip, over))
    return hints
