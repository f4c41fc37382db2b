"""Shared state of one analysis run: the model being built, diagnostics and references."""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable

from rdcd_core import diagnostics as diag
from rdcd_core.semantics.model import Model, Reference
from rdcd_core.source import Span
from rdcd_core.syntax import ast


class Context:
    def __init__(self, model: Model) -> None:
        self.model = model
        self._seen: set[tuple[str, int, int]] = set()
        self._ref_spans: set[tuple[int, int]] = set()
        # ``role`` and the roles it extends, nearest first (cached): the passes ask very often, and
        # a dict lookup costs less than a method call
        self.ancestors: Callable[[str], list[str]] = _Ancestors(model).__getitem__
        self.folding: set[int] = set()  # ids of constant symbols being folded (cycle detection)
        self.folded: set[int] = set()
        # plain-method calls: id(caller MethodDecl) -> [(callee MethodDecl, call name)]
        self.call_edges: dict[int, list[tuple[ast.MethodDecl, ast.Name]]] = {}
        self.methods_by_id: dict[int, ast.MethodDecl] = {}
        self.observed: dict[int, list[tuple[str, ast.Name]]] = {}  # id(Invariant) -> roles
        # for assumeRole scoping through inlined plain methods (inlining.py)
        self.assumes: dict[int, set[str]] = {}  # id(MethodDecl) -> mixins it assumes itself
        self.installs_handler: set[int] = set()  # ids of methods that call handleEvent
        # (callee, call name, mixins played at the call, inside an assumeRole block)
        self.inlined: list[tuple[ast.MethodDecl, ast.Name, tuple[str, ...], bool]] = []
        # roles the code observes at run time (connected_role, Role.cmd()) and mixins it assumes
        self.observed_roles: dict[str, ast.Name] = {}
        self.assumed_mixins: dict[str, ast.Name] = {}
        self.read_states: set[int] = set()  # ids of the StateSymbols read somewhere
        self.written_states: set[int] = set()
        self.role_state_owners: dict[str, str] | None = None  # states.py, once the roles are built

    # -- diagnostics -------------------------------------------------------------------
    def report(self, code: str, span: Span, message: str, *,
               related: Iterable[diag.Related] = (), fixes: Iterable[diag.Fix] = ()) -> None:
        """Adds a diagnostic; a second one with the same code and range is dropped."""
        key = (code, span.start, span.end)
        if key in self._seen:
            return
        self._seen.add(key)
        self.model.diagnostics.append(
            diag.make(code, span, message, related=tuple(related), fixes=tuple(fixes)))

    # -- references --------------------------------------------------------------------
    def reference(self, name: ast.Name, kind: str, target: str, is_definition: bool = False) -> None:
        key = (name.span.start, name.span.end)
        if key in self._ref_spans or not name.text:
            return
        self._ref_spans.add(key)
        self.model.references.append(Reference(name, kind, target, is_definition))

    # -- hierarchy ---------------------------------------------------------------------
    def is_subrole(self, role: str, ancestor: str) -> bool:
        return ancestor in self.ancestors(role)


class _Ancestors(dict[str, list[str]]):
    """role -> ``model.ancestors(role)``, computed on first use."""

    def __init__(self, model: Model) -> None:
        super().__init__()
        self.model = model

    def __missing__(self, role: str) -> list[str]:
        chain = self[role] = self.model.ancestors(role)
        return chain


def did_you_mean(name: str, candidates: Iterable[str], span: Span) -> tuple[str, tuple[diag.Fix, ...]]:
    """A message suffix and the replacement fix for an unknown ``name`` written at ``span``."""
    matches = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    if not matches:
        return "", ()
    best = matches[0]
    return f"; did you mean '{best}'?", (diag.Fix(f"replace with '{best}'", (diag.TextEdit(span, best),)),)
