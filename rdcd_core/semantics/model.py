"""The checked Program model: what the semantic analysis produces and what the compiler, the
formatter's callers and the language server read.

``rdcd_core.semantics.analyze(program_ast) -> Model`` builds it (with diagnostics); it is built
even for programs with errors, as far as it can be.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum

from rdcd_core import diagnostics as diag
from rdcd_core.fastinit import fast_init
from rdcd_core.syntax import ast
from rdcd_core.types import Type

ROOT_ROLE = "Module"


class RoleKind(StrEnum):
    CONCRETE = "concrete"
    ABSTRACT = "abstract"
    MIXIN = "mixin"


@fast_init
@dataclass(frozen=True, slots=True)
class Value:
    """A folded compile-time value: an int8, or the code of an axis, dir, event or role."""

    type: Type
    value: int


@dataclass(slots=True)
class ConstantSymbol:
    name: str
    owner: str  # the role whose declaration this entry is (after copy-down)
    declaration: ast.Name  # where it is declared (abstract) or defined
    definition: ast.ConstantDef | None  # None while abstract
    value: Value | None  # folded value; None if abstract or not foldable
    type: Type | None = None  # the constant's type (for an abstract one: that of its definitions)


@dataclass(slots=True)
class MethodSymbol:
    name: str
    owner: str  # the role that declares the body (or the abstract declaration)
    decl: ast.MethodDecl
    kind: ast.MethodKind

    @property
    def is_abstract(self) -> bool:
        return self.decl.body is None


@dataclass(slots=True)
class StateSymbol:
    """A state: module state (``owner`` None, kept across role changes) or role state (set to its
    initial value whenever the module takes the role)."""

    name: str
    owner: str | None  # the role that declares it; None for module state
    decl: ast.StateDecl
    initial: int = 0  # the folded initial value
    index: int = -1  # its byte in the module's state memory (``Model.state_layout``)
    published: bool = False  # neighbours read it (neighbours.s, children.s): sent on every change
    travelling: bool = False  # its value travels with the program from module to module

    @property
    def is_module_state(self) -> bool:
        return self.owner is None


@dataclass(slots=True)
class InvariantSymbol:
    owner: str
    decl: ast.Invariant


@dataclass(slots=True)
class RoleSymbol:
    name: str
    kind: RoleKind
    decl: ast.RoleDecl | None  # None only for the predefined root `Module`
    parent: str | None  # the role it extends (None for Module, and for a mixin)
    modifies: str | None  # for a mixin: the role it modifies
    # After copy-down (inherited members included, overrides replacing them). For a mixin these
    # hold only its own members.
    constants: dict[str, ConstantSymbol] = field(default_factory=dict)
    methods: dict[str, MethodSymbol] = field(default_factory=dict)
    invariants: list[InvariantSymbol] = field(default_factory=list)
    states: dict[str, StateSymbol] = field(default_factory=dict)  # role state, inherited included

    @property
    def is_mixin(self) -> bool:
        return self.kind is RoleKind.MIXIN


@fast_init
@dataclass(frozen=True, slots=True)
class Reference:
    """A name occurrence resolved to a symbol: for navigation, rename, highlight and hover.

    ``kind`` is one of: role, constant, method, command, primitive, predefined, state, parameter.
    ``target`` is the role name (role), ``Role.member`` (constant, method, command),
    or the primitive / predefined value name; for a state ``Role.name`` (role state) or
    ``name`` (module state); for a parameter ``Role.method.name``. ``is_definition`` marks
    declarations.
    """

    name: ast.Name
    kind: str
    target: str
    is_definition: bool = False


@dataclass(slots=True)
class Model:
    program: ast.Program
    roles: dict[str, RoleSymbol]  # includes the root `Module`
    deployment: list[str]  # deployed role names, in order (valid ones only)
    diagnostics: list[diag.Diagnostic]
    references: list[Reference] = field(default_factory=list)
    states: dict[str, StateSymbol] = field(default_factory=dict)  # module state

    def all_states(self) -> list[StateSymbol]:
        """Module state, then every role's own role state (each declaration once)."""
        found = list(self.states.values())
        for role in self.roles.values():
            found += [s for s in role.states.values() if s.owner == role.name]
        return found

    # -- hierarchy queries -------------------------------------------------------------
    def ancestors(self, name: str) -> list[str]:
        """``name`` and the roles it extends, nearest first, up to Module (cycles cut)."""
        chain: list[str] = []
        seen: set[str] = set()  # a set: long chains of roles stay linear
        current: str | None = name
        while current is not None and current in self.roles and current not in seen:
            chain.append(current)
            seen.add(current)
            current = self.roles[current].parent
        return chain

    def is_subrole(self, name: str, ancestor: str) -> bool:
        """``name`` is ``ancestor`` or extends it, directly or not."""
        return ancestor in self.ancestors(name)

    def subroles(self, name: str) -> list[str]:
        """Every non-mixin role that is ``name`` or extends it."""
        return [r for r, s in self.roles.items() if not s.is_mixin and self.is_subrole(r, name)]

    def concrete_subroles(self, name: str) -> list[str]:
        return [r for r in self.subroles(name) if self.roles[r].kind is RoleKind.CONCRETE]

    def mixins_of(self, name: str) -> list[str]:
        """Mixins applicable to role ``name`` (they modify it or one of its ancestors)."""
        ancestors = set(self.ancestors(name))
        return [r for r, s in self.roles.items() if s.is_mixin and s.modifies in ancestors]

    def role_of(self, decl: ast.RoleDecl) -> RoleSymbol | None:
        symbol = self.roles.get(decl.name.text)
        return symbol if symbol is not None and symbol.decl is decl else None

    @property
    def has_errors(self) -> bool:
        return any(d.severity is diag.Severity.ERROR for d in self.diagnostics)
