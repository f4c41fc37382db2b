"""Event handlers too large for a fragment (issue 25): the handler keeps the leading statements
that fit, and its run goes on (``CONTINUE_COMMAND``) in a chain of commands with the rest.

The commands take spare command numbers of the role (``chain.Spares``) and are installed for the
role by entry items placed before every other item of the role, so that a module has them before
it can install the handler. ``CONTINUE_COMMAND`` goes on in the same run with the same argument
(the event number): the split handler runs the same statements in the same run as the unsplit
one. Only on a target that runs ``CONTINUE_COMMAND`` (not ``--target original``); a handler of
one statement, or one that cannot get numbers, stays whole (W601 names it when it is too large).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from rdcd_core.compiler.chain import Spares, _flat
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.discovery import continuation_code
from rdcd_core.compiler.entry import EntryItem
from rdcd_core.compiler.exprgen import emit
from rdcd_core.compiler.ir import Body, Item
from rdcd_core.compiler.stmtgen import statements
from rdcd_core.syntax import ast
from vm.isa.opcodes import USER_COMMAND_BASE

# a handler's fragment holds more than the handler: the wrapper of a continuation fragment (SLEEP,
# the role test, the jump, MIGRATE_CONTINUE) and the HANDLE_EVENT instruction
OVERHEAD = 12


@dataclass(slots=True)
class HandlerSplitter:
    """``ctx.split_handler`` while the planner makes a role's entry items."""

    fits: Callable[[list[Item]], bool]  # the planner's check of a fragment's code
    size: Callable[[list[Item]], int]  # laid out, optimised
    budget: int
    spares: Spares
    made: dict[tuple, Body] = field(default_factory=dict)  # by role, handler block and mixins
    pending: dict[str, list[EntryItem]] = field(default_factory=dict)  # role -> install items

    def __call__(self, block: ast.Block, body: Body, ctx: Context) -> Body:
        if self.size(body.code) <= self.budget - OVERHEAD:
            return body
        key = (ctx.role, id(block), tuple(ctx.mixins))
        if key not in self.made:
            self.made[key] = self._split(block, body, ctx)
        return self.made[key]

    def _split(self, block: ast.Block, body: Body, ctx: Context) -> Body:
        stmts = _flat(list(block.statements))
        if len(stmts) < 2:
            return body
        role_id = ctx.table.id_of(ctx.role) or 0
        first = 1  # the longest prefix that fits with the jump
        while first < len(stmts) and self.size(_code(stmts[:first + 1], ctx, USER_COMMAND_BASE)) \
                <= self.budget - OVERHEAD:
            first += 1
        parts: list[list[ast.Stmt]] = []
        rest = stmts[first:]
        while rest:
            k = 1
            while k < len(rest) and self.fits(_alone(ctx, _install(role_id, USER_COMMAND_BASE, rest[:k + 1],
                                                                    ctx, USER_COMMAND_BASE))):
                k += 1
            parts.append(rest[:k])
            rest = rest[k:]
        numbers: list[int] = []
        for _ in parts:
            number = self.spares.take(ctx.role)
            if number is None:
                for taken in numbers:
                    self.spares.give_back(ctx.role, taken - USER_COMMAND_BASE)
                return body
            numbers.append(USER_COMMAND_BASE + number)
        items = []
        for j, part in enumerate(parts):
            following = numbers[j + 1] if j + 1 < len(parts) else 0
            code = _install(role_id, numbers[j], part, ctx, following)
            span = part[0].span.cover(part[-1].span)
            items.append(EntryItem("command", code, span, "", part[0] if len(part) == 1 else None))
        self.pending.setdefault(ctx.role, []).extend(reversed(items))  # the last part first
        return Body(_code(stmts[:first], ctx, numbers[0]))


def _code(stmts: list[ast.Stmt], ctx: Context, following: int) -> list[Item]:
    """``stmts`` as a stored body that goes on in command ``following`` (0: ends the handler)."""
    code: list[Item] = []
    saved, ctx.in_body = ctx.in_body, True
    try:
        statements(stmts, ctx, code)
    finally:
        ctx.in_body = saved
    if following:
        emit(code, "CONTINUE_COMMAND", following, span=stmts[-1].span)
    else:
        emit(code, "END_TERMINATE", span=stmts[-1].span)
    return code


def _install(role_id: int, number: int, stmts: list[ast.Stmt], ctx: Context, following: int) -> list[Item]:
    code: list[Item] = []
    emit(code, "INSTALL_COMMAND", role_id, number, Body(_code(stmts, ctx, following)),
         span=stmts[0].span.cover(stmts[-1].span))
    return code


def _alone(ctx: Context, code: list[Item]) -> list[Item]:
    """``code`` as an entry item alone in a continuation fragment."""
    span = next(item.span for item in code if getattr(item, "span", None) is not None)
    return continuation_code([(ctx, [EntryItem("command", code, span)])])
