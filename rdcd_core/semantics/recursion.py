"""Plain methods are inlined by the compiler, so a cycle of self.m() calls is an error (§5.1)."""

from __future__ import annotations

from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context
from rdcd_core.syntax import ast


def check_recursion(ctx: Context) -> None:
    edges = ctx.call_edges
    state: dict[int, int] = {}  # 1: on the DFS path, 2: done
    for start in list(edges):
        if state.get(start):
            continue
        path: list[int] = [start]
        names: list[str] = [ctx.methods_by_id[start].name.text]
        iterators = [iter(edges.get(start, ()))]
        state[start] = 1
        while iterators:
            step = next(iterators[-1], None)
            if step is None:
                state[path.pop()] = 2
                names.pop()
                iterators.pop()
                continue
            callee, call_name = step
            key = id(callee)
            ctx.methods_by_id.setdefault(key, callee)
            if state.get(key) == 1:
                _report(ctx, names[path.index(key):], callee, call_name)
            elif not state.get(key):
                state[key] = 1
                path.append(key)
                names.append(callee.name.text)
                iterators.append(iter(edges.get(key, ())))


def _report(ctx: Context, cycle: list[str], callee: ast.MethodDecl, call_name: ast.Name) -> None:
    names = [*cycle, callee.name.text]
    if len(names) > 12:  # keep the message one readable line
        names = [*names[:6], f"... ({len(names) - 12} more)", *names[-6:]]
    chain = " -> ".join(names)
    ctx.report(codes.RECURSION, call_name.span,
               f"recursive call {chain}; plain methods are inlined, so recursion is not allowed")
