"""Diagnostics are values (docs/architecture.md rule 2): the same objects feed the CLI, the LSP and the tests.

Codes are stable. Each layer registers its codes with ``define_code`` in its own ``codes.py``;
``all_codes()`` gathers them for ``docs/diagnostics.md`` and for tests.
Groups: E0xx syntax; E1xx roles and hierarchy; E2xx names and types; E3xx methods, calls and
blocks; E4xx assumeRole; E5xx deployment and discovery; E6xx target limits (compiler);
W-codes are the warnings of the same groups.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from rdcd_core.source import Span


class Severity(IntEnum):
    """Numbered as in LSP's DiagnosticSeverity."""

    ERROR = 1
    WARNING = 2
    INFORMATION = 3
    HINT = 4

    @property
    def label(self) -> str:
        return {1: "error", 2: "warning", 3: "info", 4: "hint"}[int(self)]


@dataclass(frozen=True, slots=True)
class TextEdit:
    span: Span
    new_text: str


@dataclass(frozen=True, slots=True)
class Fix:
    title: str
    edits: tuple[TextEdit, ...]


@dataclass(frozen=True, slots=True)
class Related:
    span: Span
    message: str


@dataclass(frozen=True, slots=True)
class Diagnostic:
    code: str
    severity: Severity
    span: Span
    message: str
    related: tuple[Related, ...] = ()
    fixes: tuple[Fix, ...] = ()


@dataclass(frozen=True, slots=True)
class CodeInfo:
    code: str
    severity: Severity
    title: str
    example: str  # a small program (or fragment) that triggers it


_REGISTRY: dict[str, CodeInfo] = {}


def define_code(code: str, severity: Severity, title: str, example: str) -> str:
    """Registers a diagnostic code and returns it (use: ``E_X = define_code(...)``)."""
    existing = _REGISTRY.get(code)
    if existing is not None and existing.title != title:
        raise ValueError(f"diagnostic code {code} defined twice")
    _REGISTRY[code] = CodeInfo(code, severity, title, example)
    return code


def all_codes() -> list[CodeInfo]:
    """Every registered code, sorted; imports the layers so that all are registered."""
    import importlib

    for module in ("rdcd_core.syntax.codes", "rdcd_core.semantics.codes", "rdcd_core.compiler.codes",
                   "rdcd_core.sequences.codes"):
        try:
            importlib.import_module(module)
        except ModuleNotFoundError:
            pass
    return sorted(_REGISTRY.values(), key=lambda info: info.code)


def code_info(code: str) -> CodeInfo | None:
    all_codes()
    return _REGISTRY.get(code)


def make(code: str, span: Span, message: str, *, related: tuple[Related, ...] = (),
         fixes: tuple[Fix, ...] = (), severity: Severity | None = None) -> Diagnostic:
    """A diagnostic with the registered severity of ``code`` (unless overridden)."""
    info = _REGISTRY.get(code)
    chosen = severity if severity is not None else (info.severity if info else Severity.ERROR)
    return Diagnostic(code, chosen, span, message, related, fixes)
