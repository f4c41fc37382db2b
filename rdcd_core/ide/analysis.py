"""One analysed text: the check result, a name index for lookups, and a lazily compiled program."""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any

from rdcd_core import diagnostics as diag
from rdcd_core.semantics.model import Model, Reference
from rdcd_core.source import LineIndex
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import ParseResult


@dataclass
class Analysis:
    text: str
    program: ast.Program | None
    model: Model | None
    diagnostics: list[diag.Diagnostic]
    _line_index: LineIndex | None = None
    _ref_starts: list[int] | None = None
    _refs: list[Reference] = field(default_factory=list)
    _compiled: Any = None
    _compile_tried: bool = False
    cache: dict[str, Any] = field(default_factory=dict)  # derived data of this text, per feature
    parsed: ParseResult | None = None  # for reuse by the analysis of the next edit
    target: str = "default"  # the vm.isa.targets name the program is checked and compiled for
    traces: dict[int, Any] = field(default_factory=dict)  # each sequence's run (rdcd_core/sequences)

    @property
    def line_index(self) -> LineIndex:
        if self._line_index is None:
            self._line_index = LineIndex(self.text)
        return self._line_index

    @property
    def has_syntax_errors(self) -> bool:
        return any(d.code.startswith("E0") and d.severity is diag.Severity.ERROR for d in self.diagnostics)

    # -- references --------------------------------------------------------------------------
    def references(self) -> list[Reference]:
        if self._ref_starts is None:
            refs = list(self.model.references) if self.model is not None else []
            refs.sort(key=lambda r: (r.name.span.start, r.name.span.end))
            self._refs = refs
            self._ref_starts = [r.name.span.start for r in refs]
        return self._refs

    def reference_at(self, offset: int) -> Reference | None:
        """The resolved name that covers ``offset`` (its end included, as editors expect)."""
        refs = self.references()
        assert self._ref_starts is not None
        position = bisect.bisect_right(self._ref_starts, offset) - 1
        for candidate in (position, position - 1):
            if 0 <= candidate < len(refs) and refs[candidate].name.span.contains(offset):
                return refs[candidate]
        return None

    # -- compiled program (for fragment sizes) ------------------------------------------------
    def compiled(self) -> Any:
        """The compiled program, or None when the program has errors or the compiler fails."""
        if not self._compile_tried:
            self._compile_tried = True
            if self.model is not None and not self.model.has_errors:
                try:
                    from rdcd_core.compiler import compile_model

                    self._compiled = compile_model(self.model, target=self.target)
                except Exception:  # the editor keeps working without sizes
                    self._compiled = None
        return self._compiled


def analyze(text: str, previous: Analysis | None = None, target: str = "default") -> Analysis:
    """Checks ``text`` for ``target``; never raises (a front-end crash becomes one diagnostic).
    ``previous``, the analysis of an earlier version of the text, only makes it faster."""
    try:
        from rdcd_core.frontend import check_text

        result = check_text(text, previous=previous.parsed if previous is not None else None,
                            target=target)
        return Analysis(text, result.program, result.model, list(result.diagnostics),
                        _compiled=result.compiled, _compile_tried=result.compiled is not None,
                        parsed=result.parsed, target=target, traces=result.traces)
    except Exception as error:  # DESIGN rule 2 says this cannot happen; the editor must survive it
        from rdcd_core.semantics.codes import INTERNAL_ERROR
        from rdcd_core.source import Span

        crash = diag.make(INTERNAL_ERROR, Span(0, 0), f"internal error: {error}")
        return Analysis(text, None, None, [crash])

