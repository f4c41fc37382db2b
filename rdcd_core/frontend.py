"""The front end in one call: parse, analyze and (for error-free programs) check target limits.

The CLI, the language server and the tests all use ``check_text``; it never raises on user input.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from rdcd_core import diagnostics as diag
from rdcd_core.gcpause import gc_paused
from rdcd_core.semantics import analyze
from rdcd_core.semantics.codes import INTERNAL_ERROR
from rdcd_core.semantics.model import Model
from rdcd_core.source import LineIndex, Span
from rdcd_core.syntax import ast
from rdcd_core.syntax.consequences import one_error_per_mistake
from rdcd_core.syntax.parser import ParseResult, parse


@dataclass
class CheckResult:
    text: str
    program: ast.Program
    model: Model
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    # The CompiledProgram the target checks were made on (error-free programs only): kept so that
    # the editor's fragment sizes do not compile the same text a second time.
    compiled: Any = None
    parsed: ParseResult | None = None  # the parse of ``text``, for reuse by the check of an edit
    # the run of each sequence through the lattice model, by its index (docs/reconfiguration.md)
    traces: dict[int, Any] = field(default_factory=dict)

    @property
    def has_errors(self) -> bool:
        return any(d.severity is diag.Severity.ERROR for d in self.diagnostics)

    @cached_property
    def line_index(self) -> LineIndex:
        """Lines and columns of ``text``, built when a renderer first asks."""
        return LineIndex(self.text)


def check_text(text: str, *, packet_budget: int = 50, previous: ParseResult | None = None,
               target: str = "default", config: str | None = None) -> CheckResult:
    """Syntax and semantic diagnostics of ``text`` (plus the compiler's for ``target``, a name of
    ``vm.isa.targets.TARGETS``, when error-free).

    ``previous``, the parse of an earlier version of the text (an editor's), only makes it faster.
    ``config``: the starting configuration of the program's sequences (else the one each names).
    """
    with gc_paused():
        return _check(text, packet_budget, previous, target, config)


def _check(text: str, packet_budget: int, previous: ParseResult | None,
           target: str = "default", config: str | None = None) -> CheckResult:
    try:
        parsed = parse(text, previous)
    except Exception as error:  # a parser bug: report it, keep the editor and the CLI alive
        empty = ast.Program((), None, Span(0, len(text)))
        return CheckResult(text, empty, Model(empty, {}, [], []), [_internal(error, "parsing")])
    result = CheckResult(text, parsed.program, Model(parsed.program, {}, [], []),
                         list(parsed.diagnostics), parsed=parsed)
    syntax = result.diagnostics
    try:
        result.model = analyze(parsed.program)
    except Exception as error:  # a bug must not take the editor or the CLI down
        result.diagnostics.append(_internal(error, "semantic analysis"))
        return _sorted(result)
    # one error per mistake: what the checker finds in a statement recovery repaired is a
    # consequence of the syntax error (rdcd_core.syntax.consequences)
    result.diagnostics = one_error_per_mistake(parsed.program, syntax, result.model.diagnostics)
    if not result.has_errors and parsed.program.sequences:
        result.diagnostics.extend(_sequence_diagnostics(result, config))
    if not result.has_errors:
        result.diagnostics.extend(_target_diagnostics(result, packet_budget, target))
    return _sorted(result)


def _target_diagnostics(result: CheckResult, packet_budget: int, target: str) -> list[diag.Diagnostic]:
    """The target limits (docs/language.md): the program is compiled and kept on ``result``."""
    from rdcd_core.compiler import compile_model  # the layer above: imported when needed

    try:
        result.compiled = compile_model(result.model, packet_budget=packet_budget, target=target)
    except Exception as error:  # the compiler is another layer: report, do not crash
        return [_internal(error, "compilation")]
    return list(result.compiled.diagnostics)


def _sequence_diagnostics(result: CheckResult, config: str | None) -> list[diag.Diagnostic]:
    """Each sequence run through the lattice model from its starting configuration."""
    from rdcd_core.sequences.check import lattice_diagnostics

    try:
        found, result.traces = lattice_diagnostics(result.model, config)
    except Exception as error:  # a bug of the sequence checker must not crash the CLI or editor
        return [_internal(error, "the sequence check")]
    return found


def _internal(error: Exception, stage: str) -> diag.Diagnostic:
    return diag.make(INTERNAL_ERROR, Span(0, 0),
                     f"internal error during {stage}: {type(error).__name__}: {error}; "
                     "please report this bug")


def _sorted(result: CheckResult) -> CheckResult:
    result.diagnostics.sort(key=lambda d: (d.span.start, d.span.end, d.code))
    return result
