"""Builds the AST during parsing: one method per grammar rule, called by Lark's tree builder.

Every child is either a ``Tok`` (all terminals are named, so keywords and punctuation are kept
and give the exact spans), an AST node, a list (``args``), a tuple (super-role clauses), a Lark
``Tree`` of a repetition helper (already spliced by Lark), or ``None`` for an absent ``[...]``.
"""

from __future__ import annotations

import threading
from collections import defaultdict
from typing import Any

from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.syntax.lexer import Tok

_HUGE = 10**18  # stands for integer literals too long to convert; semantics reports the range
# Two limits keep the later passes, which recurse over trees, within Python's recursion limit (and
# dataclass ==): how deeply constructs are nested in one another (brackets, calls, unary operators,
# blocks, ifs), and the height of the tree, which chains also add to though nothing in them is nested:
# each operator of a + b + c + … (left-associative) and each 'else if' is a level of the tree.
MAX_DEPTH = 100
MAX_HEIGHT = 300


class _Depths(threading.local):
    """Nesting depth and tree height of the composite nodes built by the current parse (of this
    thread), and the nodes where a limit is first passed."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> tuple[list, list]:
        self.depth: defaultdict[int, int] = defaultdict(int)  # by id; 0 for tokens and leaves
        self.height: defaultdict[int, int] = defaultdict(int)
        self.keep: list = []  # holds the nodes, so that their ids stay unique during the parse
        self.too_deep: list = []
        self.too_long: list = []
        return self.too_deep, self.too_long


DEPTHS = _Depths()


def _nested(node: Any, children: Any, depth: int | None = None) -> Any:
    """Records ``node``, one level above ``children`` (``depth``: its nesting depth, if not that)."""
    depths, heights = DEPTHS.depth, DEPTHS.height
    depth_of, height_of = depths.get, heights.get
    deepest = highest = 0
    for child in children:  # plain ifs: this runs for every node of every parse
        key = id(child)
        level = depth_of(key, 0)
        if level > deepest:
            deepest = level
        level = height_of(key, 0)
        if level > highest:
            highest = level
    mine = deepest + 1 if depth is None else depth
    key = id(node)
    depths[key] = mine
    heights[key] = highest + 1
    DEPTHS.keep.append(node)
    if mine > MAX_DEPTH >= deepest:
        DEPTHS.too_deep.append(node)
    elif highest == MAX_HEIGHT and deepest <= MAX_DEPTH:
        DEPTHS.too_long.append(node)
    return node


def _span(first: Any, last: Any) -> Span:
    start = first.start if isinstance(first, Tok) else first.span.start
    end = last.end if isinstance(last, Tok) else last.span.end
    return Span(start, end)


def _name(tok: Tok) -> ast.Name:
    return ast.Name(tok.value, Span(tok.start, tok.end))


def _args(children: list) -> tuple:
    """The arguments of a call: the list of the ``args`` rule, just before the ')' if any."""
    args = children[-2]
    return tuple(args) if isinstance(args, list) else ()


class AstBuilder:
    """The ``transformer`` given to Lark (methods are looked up by rule name or alias)."""

    # ------------------------------------------------------------------ program and roles

    def start(self, c: list) -> tuple:
        roles = tuple(x for x in c if isinstance(x, ast.RoleDecl))
        states = tuple(x for x in c if isinstance(x, ast.StateDecl))
        deployment = c[-1] if c and isinstance(c[-1], ast.Deployment) else None
        sequences = tuple(x for x in c if isinstance(x, ast.Sequence))
        return roles, deployment, states, sequences

    def role(self, c: list) -> ast.RoleDecl:
        abstract, role_kw, name, sup, lbrace = c[0], c[1], c[2], c[3], c[4]
        first = abstract if abstract is not None else role_kw
        extends = sup[1] if sup is not None and sup[0] == "extends" else None
        modifies = sup[1] if sup is not None and sup[0] == "modifies" else None
        return ast.RoleDecl(
            name=_name(name), is_abstract=abstract is not None, extends=extends, modifies=modifies,
            members=tuple(c[5:-1]), span=_span(first, c[-1]), header_span=_span(first, lbrace),
            abstract_span=Span(abstract.start, abstract.end) if abstract is not None else None)

    def extends_clause(self, c: list) -> tuple:
        return "extends", _name(c[1])

    def modifies_clause(self, c: list) -> tuple:
        return "modifies", _name(c[1])

    def deployment(self, c: list) -> ast.Deployment:
        names = tuple(_name(x) for x in c if isinstance(x, Tok) and x.type == "NAME")
        return ast.Deployment(names, _span(c[0], c[-1]))

    # ------------------------------------------------------------------ sequences

    def sequence(self, c: list) -> ast.Sequence:
        # SEQUENCE NAME [LPAR NAME RPAR] [NAME] LBRACE item* RBRACE; an absent [...] gives Nones
        config = _name(c[3]) if c[3] is not None else None
        modifier = _name(c[5]) if c[5] is not None else None
        lbrace = c[6]
        items = tuple(x for x in c[7:-1] if isinstance(x, (ast.SeqStep, ast.SeqParallel)))
        return ast.Sequence(_name(c[1]), config, items, _span(c[0], c[-1]), _span(c[0], lbrace), modifier)

    def seq_parallel(self, c: list) -> ast.SeqParallel:
        steps = tuple(x for x in c[2:-1] if isinstance(x, ast.SeqStep))
        return ast.SeqParallel(steps, _span(c[0], c[-1]))

    def seq_step(self, c: list) -> ast.SeqStep:
        # NAME [LPAR expr RPAR] DOT NAME LPAR [args] RPAR SEMI
        condition = c[2]
        args = c[-3] if isinstance(c[-3], list) else []
        node = ast.SeqStep(_name(c[0]), condition, _name(c[5]), tuple(args), _span(c[0], c[-1]))
        return _nested(node, (condition, *args))

    # ------------------------------------------------------------------ members

    def abstract_constants(self, c: list) -> ast.AbstractConstants:
        names = tuple(_name(x) for x in c if x.type == "NAME")
        return ast.AbstractConstants(names, _span(c[0], c[-1]))

    def constant_def(self, c: list) -> ast.ConstantDef:
        return ast.ConstantDef(_name(c[1]), c[3], _span(c[0], c[4]))

    def state_decl(self, c: list) -> ast.StateDecl:
        travelling, rest = c[0], c[1:]
        first = travelling if travelling is not None else rest[0]
        return ast.StateDecl(_name(rest[1]), rest[3], _span(first, rest[4]), travelling is not None)

    def invariant(self, c: list) -> ast.Invariant:
        return ast.Invariant(c[0], _span(c[0], c[1]))

    def method(self, c: list) -> ast.MethodDecl:
        modifiers = tuple(c[:-5])
        args = c[-3] if isinstance(c[-3], list) else []
        params = tuple(arg.name for arg in args if isinstance(arg, ast.NameRef))
        bad = tuple(arg.span for arg in args if not isinstance(arg, ast.NameRef))
        body = c[-1] if isinstance(c[-1], ast.Block) else None
        return ast.MethodDecl(_name(c[-5]), modifiers, body, _span(c[0], c[-1]), params, bad)

    def modifier(self, c: list) -> ast.Modifier:
        return ast.Modifier(c[0].value, Span(c[0].start, c[0].end))

    # ------------------------------------------------------------------ statements

    def block(self, c: list) -> ast.Block:
        statements = tuple(c[1:-1])
        return _nested(ast.Block(statements, _span(c[0], c[-1])), statements)

    def empty_stmt(self, c: list) -> ast.EmptyStmt:
        return ast.EmptyStmt(Span(c[0].start, c[0].end))

    def call_stmt(self, c: list) -> ast.CallStmt:
        return _nested(ast.CallStmt(c[0], _span(c[0], c[1])), (c[0],))

    def assign_stmt(self, c: list) -> ast.AssignStmt:
        return _nested(ast.AssignStmt(_name(c[0]), c[2], _span(c[0], c[3])), (c[2],))

    def misplaced_assign(self, c: list) -> ast.AssignStmt:
        return self.assign_stmt(c)

    def if_stmt(self, c: list) -> ast.IfStmt:
        else_kw = c[5] if len(c) > 6 else None
        else_body = c[6] if else_kw is not None else None
        last = else_body if else_body is not None else c[4]
        node = ast.IfStmt(c[2], c[4], else_body, _span(c[0], last),
                          Span(else_kw.start, else_kw.end) if else_kw is not None else None)
        # if … else if … else if … is one level however long, like a + b + c
        depths = DEPTHS.depth
        chained = isinstance(else_body, ast.IfStmt)
        depth = max(depths[id(c[2])], depths[id(c[4])], depths[id(else_body)] - chained) + 1
        return _nested(node, (c[2], c[4], else_body), depth)

    # ------------------------------------------------------------------ calls

    def self_call(self, c: list) -> ast.SelfCall:
        args = _args(c)
        node = ast.SelfCall(_name(c[2]), args, len(c) > 3, _span(c[0], c[-1]))
        return _nested(node, args) if args else node

    def function_call(self, c: list) -> ast.FunctionCall:
        args = _args(c)
        return _nested(ast.FunctionCall(_name(c[0]), args, _span(c[0], c[-1])), args)

    def global_call(self, c: list) -> ast.GlobalCall:
        args = _args(c)
        node = ast.GlobalCall(_name(c[0]), _name(c[2]), args, _span(c[0], c[-1]))
        return _nested(node, args) if args else node

    def args(self, c: list) -> list:
        return [x for x in c if not isinstance(x, Tok)]

    # ------------------------------------------------------------------ expressions

    def binary(self, c: list) -> ast.Binary:
        left, op, right = c
        depths = DEPTHS.depth
        # a + b + c is one level however long (the left operand is the chain so far): only what is
        # nested in an operand adds to the depth
        chained = isinstance(left, ast.Binary)
        depth = max(depths[id(left)] - chained, depths[id(right)]) + 1
        node = ast.Binary(op.value, left, right, _span(left, right), Span(op.start, op.end))
        return _nested(node, (left, right), depth)

    def unary(self, c: list) -> ast.Unary:
        return _nested(ast.Unary(c[0].value, c[1], _span(c[0], c[1])), (c[1],))

    def int_lit(self, c: list) -> ast.IntLit:
        tok = c[0]
        try:
            value = int(tok.value.lstrip("0") or "0")  # leading zeros do not count to the limit
        except ValueError:  # longer than Python converts (4300 digits)
            value = _HUGE
        return ast.IntLit(value, Span(tok.start, tok.end))

    def name_ref(self, c: list) -> ast.NameRef:
        name = _name(c[0])
        return ast.NameRef(name, name.span)

    def neighbour_values(self, c: list) -> ast.NeighbourValues:
        where = c[2] if len(c) == 6 else None
        node = ast.NeighbourValues(_name(c[-1]), where, c[0].type == "CHILDREN", _span(c[0], c[-1]))
        return _nested(node, (where,)) if where is not None else node

    def paren(self, c: list) -> ast.Paren:
        return _nested(ast.Paren(c[1], _span(c[0], c[2])), (c[1],))
