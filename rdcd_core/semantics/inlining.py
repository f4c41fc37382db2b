"""assumeRole scoping through plain methods: they are inlined, so a plain method called inside an
assumeRole block runs in the mixin too (docs/language.md)."""

from __future__ import annotations

from rdcd_core.semantics import codes
from rdcd_core.semantics.context import Context
from rdcd_core.syntax import ast


def check_inlined_scoping(ctx: Context) -> None:
    memo: dict[int, tuple[frozenset[str], bool]] = {}
    for callee, name, played, in_assume in ctx.inlined:
        assumed, installs = _effects(ctx, callee, memo, set())
        again = sorted(assumed & set(played))
        if again:
            ctx.report(codes.NESTED_ASSUME, name.span,
                       f"'{callee.name.text}' assumes '{again[0]}' but is called where the "
                       f"module already plays '{again[0]}' (plain methods are inlined); call it "
                       "outside the assumeRole block")
        if in_assume and installs:
            ctx.report(codes.HANDLER_IN_ASSUME, name.span,
                       f"'{callee.name.text}' installs an event handler; called inside assumeRole, "
                       "the handler runs later in whatever role the module then has")


def _effects(ctx: Context, method: ast.MethodDecl, memo: dict[int, tuple[frozenset[str], bool]],
             visiting: set[int]) -> tuple[frozenset[str], bool]:
    """Mixins a plain method assumes and whether it installs a handler, callees included."""
    key = id(method)
    if key in memo:
        return memo[key]
    if key in visiting:  # recursion is reported elsewhere
        return frozenset(), False
    visiting.add(key)
    assumed = set(ctx.assumes.get(key, ()))
    installs = key in ctx.installs_handler
    for callee, _ in ctx.call_edges.get(key, ()):
        more, handler = _effects(ctx, callee, memo, visiting)
        assumed |= more
        installs = installs or handler
    visiting.discard(key)
    memo[key] = (frozenset(assumed), installs)
    return memo[key]
