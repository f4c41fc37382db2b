"""What code generation knows while it compiles code for one concrete role."""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.roletable import RoleTable, application_name
from rdcd_core.semantics.model import MethodSymbol, Model, Value
from rdcd_core.source import Span
from rdcd_core.types import PREDEFINED_VALUES, Type


@dataclass(slots=True)
class Context:
    model: Model
    table: RoleTable
    role: str  # the concrete role the code is specialised for
    strict: bool = False
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    mixins: list[str] = field(default_factory=list)  # active assumeRole mixins, innermost last
    inlining: list[str] = field(default_factory=list)
    inlined_nesting: int = 0  # tree levels the bodies in ``inlining`` add (stmtgen.nesting)
    command_numbers: dict[str, int] = field(default_factory=dict)
    cache: dict[tuple, object] = field(default_factory=dict)  # per-compilation memo
    reported: set[tuple[str, Span]] = field(default_factory=set)  # (code, span) of ``diagnostics``

    def report(self, code: str, span: Span, message: str) -> None:
        if (code, span) not in self.reported:  # a set: thousands of reports stay linear
            self.reported.add((code, span))
            self.diagnostics.append(diag.make(code, span, message))

    def scopes(self) -> list[str]:
        return [*reversed(self.mixins), self.role]

    def constant(self, name: str) -> Value | None:
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

    def ext(self, op: str, span: Span) -> None:
        if self.strict:
            self.report(codes.EXT_REFUSED, span,
                        f"this needs the extension instruction {op}; --strict-isa refuses it")
