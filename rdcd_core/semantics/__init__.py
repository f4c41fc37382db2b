"""Semantic analysis of RDCD programs: ``analyze(program) -> Model`` (docs/language.md)."""

from __future__ import annotations

import sys

from rdcd_core.semantics import codes  # noqa: F401  (registers the diagnostic codes)
from rdcd_core.semantics.model import Model
from rdcd_core.syntax import ast

_RECURSION_LIMIT = 60_000


def analyze(program: ast.Program) -> Model:
    """Builds the checked model of ``program``, with semantic diagnostics sorted by position.

    Tolerates partial trees from files with syntax errors; never raises on user input.
    """
    from rdcd_core.semantics.analysis import run

    # Expressions are checked recursively; a long chain like 1+1+…+1 nests deeply. Python 3.11
    # runs Python-to-Python calls without the C stack, so a higher limit is safe.
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, _RECURSION_LIMIT))
    try:
        return run(program)
    finally:
        sys.setrecursionlimit(limit)


__all__ = ["Model", "analyze"]
