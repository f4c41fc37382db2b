"""The compiler's output: fragments, the role table and the injection plan."""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core import diagnostics as diag
from rdcd_core.fastinit import fast_init
from rdcd_core.source import Span
from vm.isa.opcodes import SLOT_BYTES

HEADER_BYTES = 7  # program packet header (docs/vm.md)
DEFAULT_PACKET_BUDGET = 50
MAX_PROGRAM_BYTES = SLOT_BYTES  # a program store slot (docs/vm.md)


@fast_init  # one per instruction of every fragment: made in bulk
@dataclass(frozen=True, slots=True)
class SourceEntry:
    """The instruction at ``offset`` (``size`` bytes) came from ``span`` (line: 1-based or 0)."""

    offset: int
    size: int
    span: Span | None
    line: int = 0


@dataclass(slots=True)
class Fragment:
    name: str
    kind: str  # discovery | entry (startup, commands, behaviours of a role after discovery)
    role: str | None
    code: bytes
    source_map: list[SourceEntry] = field(default_factory=list)
    span: Span | None = None  # the source construct that caused the fragment
    source: tuple[int, int] = (0, 0)  # (line, end_line), 1-based; (0, 0) if unknown
    roles: list[str] = field(default_factory=list)  # the roles whose code it holds
    methods: list[str] = field(default_factory=list)  # the methods whose code it holds

    @property
    def size(self) -> int:
        return len(self.code)

    @property
    def source_lines(self) -> list[tuple[int, int]]:
        """(offset, line) of each instruction."""
        return [(entry.offset, entry.line) for entry in self.source_map]


@dataclass(frozen=True, slots=True)
class RoleEntry:
    id: int
    name: str  # a role, a mixin, or "Mixin@Role" for a mixin applied to a concrete role
    kind: str  # concrete | abstract | mixin | application
    instance_of: list[int]  # ids this role is an instance of, itself included


@dataclass(slots=True)
class StateEntry:
    """A state's byte in the module's state memory: for reports, the replay and the debugger."""

    name: str
    index: int
    initial: int
    owner: str | None  # the role of a role state; None for module state
    published: bool  # sent to the neighbours on every change
    roles: tuple[str, ...] = ()  # of a role state: every role that has it (its owner and sub-roles)


@dataclass(slots=True)
class CompiledProgram:
    fragments: list[Fragment]
    roles: list[RoleEntry]
    injection: list[str]
    packet_budget: int
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    target: str = "default"  # the vm.isa.targets description it was compiled for
    states: list[StateEntry] = field(default_factory=list)  # the state memory's layout

    @property
    def total_bytes(self) -> int:
        return sum(f.size for f in self.fragments)

    @property
    def max_fragment_bytes(self) -> int:
        return max((f.size for f in self.fragments), default=0)

    @property
    def program_budget(self) -> int:
        return self.packet_budget - HEADER_BYTES

    @property
    def has_errors(self) -> bool:
        return any(d.severity is diag.Severity.ERROR for d in self.diagnostics)

    def fragment(self, name: str) -> Fragment:
        return next(f for f in self.fragments if f.name == name)

    def role_id(self, name: str) -> int:
        return next(r.id for r in self.roles if r.name == name)
