"""The RDCD abstract syntax tree: frozen dataclasses, every node with its exact source span.

The grammar is `docs/language.md` §2. Parentheses are kept (``Paren``) so that the formatter
can reproduce what the user wrote; analyses look through them with ``unparen``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from enum import StrEnum
from typing import Any, Union

from rdcd_core.fastinit import fast_init
from rdcd_core.source import Span


@fast_init
@dataclass(frozen=True, slots=True)
class Name:
    """An identifier occurrence."""

    text: str
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class Comment:
    text: str  # including the // or /* */ delimiters
    span: Span


# ----------------------------------------------------------------------------- expressions


@fast_init
@dataclass(frozen=True, slots=True)
class IntLit:
    value: int  # non-negative as written; unary minus is a Unary node
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class NameRef:
    """A bare name in an expression: a constant, a predefined value or a role."""

    name: Name
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class Unary:
    op: str  # "-" or "!"
    operand: Expr
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class Binary:
    op: str  # || && == != < > <= >= + -
    left: Expr
    right: Expr
    span: Span
    op_span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class Paren:
    expr: Expr
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class SelfCall:
    """``self.name(args)`` or ``self.name`` (``has_parens`` False: a zero-argument query)."""

    name: Name
    args: tuple[Arg, ...]
    has_parens: bool
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class FunctionCall:
    """``name(args)``: the functions ``sizeof`` and ``connected_role``."""

    name: Name
    args: tuple[Arg, ...]
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class GlobalCall:
    """``Role.command()``: a global command call."""

    role: Name
    name: Name
    args: tuple[Arg, ...]
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class NeighbourValues:
    """``neighbours.s``, ``neighbours(where).s`` or ``children.s``: the values of module state ``s``
    that neighbours published, an argument of ``min``, ``max``, ``count`` and ``sum``."""

    name: Name
    where: Expr | None  # a direction or a connector number; None for every neighbour
    children: bool  # only the neighbours whose parent in the structure's tree is this module
    span: Span


Call = Union[SelfCall, FunctionCall, GlobalCall]
Expr = Union[IntLit, NameRef, Unary, Binary, Paren, SelfCall, FunctionCall, GlobalCall, NeighbourValues]

# ----------------------------------------------------------------------------- statements


@fast_init
@dataclass(frozen=True, slots=True)
class Block:
    statements: tuple[Stmt, ...]
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class EmptyStmt:
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class CallStmt:
    call: Call
    span: Span  # includes the trailing ';'


@fast_init
@dataclass(frozen=True, slots=True)
class IfStmt:
    condition: Expr
    then_body: Stmt
    else_body: Stmt | None
    span: Span
    else_span: Span | None = None  # the 'else' keyword


@fast_init
@dataclass(frozen=True, slots=True)
class AssignStmt:
    """``name := expr;``: a new value for a state."""

    name: Name
    value: Expr  # a Block only in erroneous programs (the checker reports it)
    span: Span  # includes the trailing ';'


Stmt = Union[Block, EmptyStmt, CallStmt, IfStmt, AssignStmt]
Arg = Union[IntLit, NameRef, Unary, Binary, Paren, SelfCall, FunctionCall, GlobalCall, NeighbourValues, Block]

# ----------------------------------------------------------------------------- members


@fast_init
@dataclass(frozen=True, slots=True)
class AbstractConstants:
    """``abstract constant a, b;``"""

    names: tuple[Name, ...]
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class ConstantDef:
    """``constant a := expr;``"""

    name: Name
    value: Expr
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class StateDecl:
    """``state s := expr;``: module state at the top level, role state in a role;
    ``travelling state s := expr;``: module state that travels with the program."""

    name: Name
    value: Expr
    span: Span
    travelling: bool = False


@fast_init
@dataclass(frozen=True, slots=True)
class Invariant:
    expr: Expr
    span: Span


class MethodKind(StrEnum):
    STARTUP = "startup"
    BEHAVIOR = "behavior"
    COMMAND = "command"
    PLAIN = "plain"


_METHOD_KINDS = {kind.value: kind for kind in MethodKind}  # faster than MethodKind(keyword)


@fast_init
@dataclass(frozen=True, slots=True)
class Modifier:
    keyword: str  # abstract | startup | behavior | command
    span: Span


@fast_init
@dataclass(frozen=True, slots=True)
class MethodDecl:
    name: Name
    modifiers: tuple[Modifier, ...]
    body: Block | None  # None for `abstract m();`
    span: Span
    params: tuple[Name, ...] = ()
    bad_params: tuple[Span, ...] = ()  # parameters that are not plain names (the checker reports them)

    @property
    def is_abstract(self) -> bool:
        return any(m.keyword == "abstract" for m in self.modifiers)

    @property
    def kind(self) -> MethodKind:
        for modifier in self.modifiers:
            if modifier.keyword != "abstract":
                return _METHOD_KINDS[modifier.keyword]
        return MethodKind.PLAIN


Member = Union[AbstractConstants, ConstantDef, StateDecl, Invariant, MethodDecl, AssignStmt]

# ----------------------------------------------------------------------------- program


@fast_init
@dataclass(frozen=True, slots=True)
class RoleDecl:
    name: Name
    is_abstract: bool
    extends: Name | None
    modifies: Name | None
    members: tuple[Member, ...]
    span: Span
    header_span: Span  # from the first keyword to the '{'
    abstract_span: Span | None = None  # the 'abstract' keyword, if present


@fast_init
@dataclass(frozen=True, slots=True)
class Deployment:
    roles: tuple[Name, ...]
    span: Span


# ----------------------------------------------------------------------------- sequences


@fast_init
@dataclass(frozen=True, slots=True)
class SeqStep:
    """``Role.action(args);`` or ``Role(condition).action(args);``: one step of a sequence."""

    role: Name
    condition: Expr | None  # which of the modules holding the role acts (None: the only one)
    action: Name  # connect | disconnect | turnQuarters | waitUntil
    args: tuple[Arg, ...]
    span: Span  # includes the trailing ';'


@fast_init
@dataclass(frozen=True, slots=True)
class SeqParallel:
    """``parallel { steps }``: steps that run at once, one stage of the sequence."""

    steps: tuple[SeqStep, ...]
    span: Span


SeqItem = Union[SeqStep, SeqParallel]


@fast_init
@dataclass(frozen=True, slots=True)
class Sequence:
    """``sequence name(config) { stages }``: a reconfiguration of the whole robot."""

    name: Name
    config: Name | None  # the configuration it starts from, for the checker
    items: tuple[SeqItem, ...]
    span: Span
    header_span: Span  # from 'sequence' to the '{'
    modifier: Name | None = None  # 'rollback': a failed step undoes the steps done, in reverse order


@fast_init
@dataclass(frozen=True, slots=True)
class Program:
    roles: tuple[RoleDecl, ...]
    deployment: Deployment | None
    span: Span
    comments: tuple[Comment, ...] = field(default=())
    states: tuple[StateDecl, ...] = field(default=())  # module state (top level)
    sequences: tuple[Sequence, ...] = field(default=())


Node = Any  # any of the dataclasses above


def unparen(expr: Expr) -> Expr:
    """The expression inside any number of parentheses."""
    while isinstance(expr, Paren):
        expr = expr.expr
    return expr


def signed_literal(expr: Expr) -> int | None:
    """The number written, when ``expr`` is one: ``150``, ``-180``, ``(-150)``; otherwise None
    (``-(150)`` negates the value 150, as the checker reads it)."""
    expr = unparen(expr)
    if isinstance(expr, Unary) and expr.op == "-":
        return -expr.operand.value if isinstance(expr.operand, IntLit) else None
    return expr.value if isinstance(expr, IntLit) else None


_NOT_CHILDREN = frozenset({"span", "op_span", "header_span", "abstract_span", "else_span", "comments",
                           "bad_params"})
_SCALAR_TYPES = frozenset({"str", "int", "bool"})  # annotations of fields that never hold a node
_CHILD_FIELDS: dict[type, tuple[str, ...]] = {}


def _child_fields(cls: type) -> tuple[str, ...]:
    names = _CHILD_FIELDS.get(cls)
    if names is None:  # dataclasses.fields() is slow: computed once per class
        names = _CHILD_FIELDS[cls] = tuple(f.name for f in fields(cls)
                                           if f.name not in _NOT_CHILDREN and f.type not in _SCALAR_TYPES)
    return names


def children(node: Node) -> list[Node]:
    """Direct child nodes (names included), in source order."""
    result: list[Node] = []
    for name in _child_fields(type(node)):
        value = getattr(node, name)
        if isinstance(value, tuple):
            result.extend([v for v in value if hasattr(v, "span")])
        elif hasattr(value, "span"):
            result.append(value)
    return result


def walk(node: Node):  # type: ignore[no-untyped-def]
    """Pre-order traversal of ``node`` and all its descendants."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        nodes = children(current)
        nodes.reverse()
        stack += nodes


def strip_spans(node: Any) -> Any:
    """A span-free, comment-free structural form of a tree, for comparing ASTs (formatter tests)."""
    if isinstance(node, tuple):
        return tuple(strip_spans(v) for v in node)
    if hasattr(node, "__dataclass_fields__") and not isinstance(node, Span):
        items = []
        for f in fields(node):
            if f.name.endswith("span") or f.name == "comments":
                continue
            items.append((f.name, strip_spans(getattr(node, f.name))))
        return (type(node).__name__, tuple(items))
    return node
