"""What code generation knows while it compiles code for one concrete role."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.ir import Body
from rdcd_core.compiler.roletable import RoleTable, application_name
from rdcd_core.semantics.model import MethodSymbol, Model, StateSymbol, Value
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.types import PREDEFINED_VALUES, Type
from vm.isa.targets import DEFAULT, Target


@dataclass(slots=True)
class Context:
    model: Model
    table: RoleTable
    role: str  # the concrete role the code is specialised for
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    mixins: list[str] = field(default_factory=list)  # active assumeRole mixins, innermost last
    inlining: list[str] = field(default_factory=list)
    inlined_nesting: int = 0  # tree levels the bodies in ``inlining`` add (stmtgen.nesting)
    command_numbers: dict[str, int] = field(default_factory=dict)
    cache: dict[tuple, object] = field(default_factory=dict)  # per-compilation memo
    reported: set[tuple[str, Span]] = field(default_factory=set)  # (code, span) of ``reported_of``
    reported_of: list | None = None
    reported_count: int = 0
    target: Target = DEFAULT  # what the code must run on (vm.isa.targets)
    # Local states (bits over geometry.LOCAL_STATES) in which the code being generated may run:
    # a discovery test knows the states its earlier tests let through, a role's code the axes its
    # invariants allow. None: any state.
    states: int | None = None
    # State: the parameter of the command whose body is being compiled (its value is the run's
    # argument), the arguments bound to the parameters of the plain methods being inlined (each
    # with the bindings of its caller), and whether roles are re-checked when values change.
    argument: str | None = None
    command: str | None = None  # the command whose body is being compiled (compiler.known)
    bindings: dict[str, tuple[object, dict]] = field(default_factory=dict)
    watched: bool = False
    in_body: bool = False  # code of a stored body (handler, command, behaviour): it never migrates
    # the planner's splitter of handlers too large for a fragment (compiler.handlers): called with
    # the handler's block and body, gives the body to install; None: handlers stay whole
    split_handler: Callable[[ast.Block, Body, Context], Body] | None = None

    def state(self, name: str) -> StateSymbol | None:
        """The state ``name`` reads in this code (role state of the role, else module state)."""
        if name in self.bindings or name == self.argument or self.constant_symbol(name):
            return None
        found = self.model.roles[self.role].states.get(name)
        return found if found is not None else self.model.states.get(name)

    def constant_symbol(self, name: str) -> bool:
        return any(name in self.model.roles[scope].constants for scope in self.scopes())

    def report(self, code: str, span: Span, message: str) -> None:
        """Adds a diagnostic unless ``diagnostics`` already has one with this code and span."""
        keys = self._reported()
        if (code, span) not in keys:
            keys.add((code, span))
            self.diagnostics.append(diag.make(code, span, message))
        self.reported_count = len(self.diagnostics)

    def _reported(self) -> set[tuple[str, Span]]:
        """The (code, span) keys of ``diagnostics``, kept in a set so that thousands of reports stay
        linear; made again when code swapped the list or changed it directly."""
        if self.reported_of is not self.diagnostics or self.reported_count != len(self.diagnostics):
            self.reported = {(d.code, d.span) for d in self.diagnostics}
            self.reported_of = self.diagnostics
        return self.reported

    def scopes(self) -> list[str]:
        return [*reversed(self.mixins), self.role]

    def constant(self, name: str) -> Value | None:
        if name in self.bindings or name == self.argument:
            return None
        for scope in self.scopes():
            symbol = self.model.roles[scope].constants.get(name)
            if symbol is not None:
                return symbol.value
        if name in PREDEFINED_VALUES:
            value = PREDEFINED_VALUES[name]
            return Value(value.type, value.code)
        if name in self.model.roles:
            role_id = self.table.id_of(name)
            return Value(Type.ROLE, role_id if role_id is not None else 0)
        return None

    def method(self, name: str) -> MethodSymbol | None:
        for scope in self.scopes():
            symbol = self.model.roles[scope].methods.get(name)
            if symbol is not None:
                return symbol
        return None

    def current_role_id(self) -> int:
        name = application_name(self.mixins[-1], self.role) if self.mixins else self.role
        return self.table.id_of(name) or 0

    def has(self, op: str) -> bool:
        """Whether the target runs instruction ``op``."""
        return self.target.implements_name(op)

    def ext(self, op: str, span: Span) -> None:
        self.need(op, span, "this needs the extension instruction")

    def need(self, op: str, span: Span, what: str) -> bool:
        """True if the target runs ``op``; otherwise reports that ``what`` cannot be compiled."""
        if self.has(op):
            return True
        self.cannot(span, f"{what} {op}, which the {self.target.name} target does not run")
        return False

    def cannot(self, span: Span, why: str) -> None:
        """Reports code that the target cannot express (E605), naming the role and why."""
        self.report(codes.EXT_REFUSED, span, f"in role {self.role}: {why}")
