"""rdcd diagnostics → LSP diagnostics (same codes, ranges and related locations)."""

from __future__ import annotations

from lsprotocol import types

from rdcd_core import diagnostics as diag
from server.convert import Positions


def to_lsp_diagnostic(diagnostic: diag.Diagnostic, positions: Positions, uri: str) -> types.Diagnostic:
    related = [
        types.DiagnosticRelatedInformation(
            location=types.Location(uri=uri, range=positions.range(r.span)), message=r.message)
        for r in diagnostic.related
    ]
    return types.Diagnostic(
        range=positions.range(diagnostic.span),
        severity=types.DiagnosticSeverity(int(diagnostic.severity)),
        code=diagnostic.code,
        source="rdcd",
        message=diagnostic.message,
        related_information=related or None,
    )


def to_lsp_diagnostics(diagnostics: list[diag.Diagnostic], positions: Positions,
                       uri: str) -> list[types.Diagnostic]:
    return [to_lsp_diagnostic(d, positions, uri) for d in diagnostics]
