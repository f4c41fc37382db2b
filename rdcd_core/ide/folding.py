"""Folding ranges: roles, method bodies, multi-line blocks and comments, the deployment."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.syntax import ast


@dataclass(frozen=True)
class Fold:
    start_line: int
    end_line: int
    kind: str = "region"  # region or comment


def folding_ranges(analysis: Analysis) -> list[Fold]:
    program = analysis.program
    if program is None:
        return []
    index = analysis.line_index
    folds: list[Fold] = []

    def add(start: int, end: int, kind: str = "region") -> None:
        first, last = index.line_col(start).line, index.line_col(end).line
        if last > first:
            folds.append(Fold(first, last, kind))

    for node in ast.walk(program):
        if isinstance(node, (ast.RoleDecl, ast.Block, ast.Deployment)):
            add(node.span.start, max(node.span.start, node.span.end - 1))
    run_start = run_end = None
    for comment in program.comments:
        if comment.text.startswith("/*"):
            add(comment.span.start, comment.span.end, "comment")
            continue
        line = index.line_col(comment.span.start).line
        if run_end is not None and line == run_end + 1:
            run_end = line
            continue
        if run_start is not None and run_end is not None and run_end > run_start:
            folds.append(Fold(run_start, run_end, "comment"))
        run_start = run_end = line
    if run_start is not None and run_end is not None and run_end > run_start:
        folds.append(Fold(run_start, run_end, "comment"))
    folds.sort(key=lambda f: (f.start_line, -f.end_line))
    return folds
