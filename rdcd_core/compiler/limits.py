"""Limits of docs/language.md that need the compiler's view: command numbers, program slots.

The number of role ids and of command-table entries is the checker's (E120, E121): the role table
has exactly the ids it counts, so the compiler does not count them again."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.entry import behaviour_numbers, methods_of
from rdcd_core.semantics.model import Model
from rdcd_core.semantics.walk import code_nodes
from rdcd_core.syntax import ast
from vm.isa.opcodes import PROGRAM_SLOTS, USER_COMMANDS


def command_limit(model: Model, commands: dict[str, int]) -> list[diag.Diagnostic]:
    found: list[diag.Diagnostic] = []
    for role in model.deployment:
        methods = methods_of(model, role, ast.MethodKind.COMMAND)
        numbers = {m.name: commands[m.name] for m in methods}
        numbers.update(behaviour_numbers(model, role, commands))
        everything = methods + methods_of(model, role, ast.MethodKind.BEHAVIOR)
        for method in everything:
            if numbers[method.name] >= USER_COMMANDS:  # more entries than that are the checker's E121
                found.append(diag.make(
                    codes.TOO_MANY_COMMANDS, method.decl.name.span,
                    f"{method.kind.value} '{method.name}' of role {role} gets no number in its "
                    f"command table of {USER_COMMANDS}: a command keeps one number in every role that "
                    "has it, and the commands it shares with other roles take the others; give the "
                    "roles fewer commands in common"))
    return _unique(found)


def program_limit(model: Model, slots: int = PROGRAM_SLOTS) -> list[diag.Diagnostic]:
    """Stored programs on a module of each role: commands, behaviours, handlers."""
    found: list[diag.Diagnostic] = []
    for role in model.deployment:
        symbol = model.roles[role]
        count = sum(1 for m in symbol.methods.values()
                    if m.kind in (ast.MethodKind.COMMAND, ast.MethodKind.BEHAVIOR) and m.decl.body)
        events = set()
        for method in symbol.methods.values():
            if method.decl.body is None:
                continue
            for node in code_nodes(method.decl.body):
                if isinstance(node, ast.SelfCall) and node.name.text == "handleEvent" and node.args:
                    # one slot per event (a new handler replaces the old): compare without spans
                    events.add(ast.strip_spans(node.args[0]))
        count += len(events)
        if count > slots and symbol.decl is not None:
            found.append(diag.make(
                codes.TOO_MANY_PROGRAMS, symbol.decl.name.span,
                f"a module playing {role} stores {count} programs (commands, behaviours, "
                f"handlers); the DCD-VM has {slots} slots"))
    return found


def _unique(items: list[diag.Diagnostic]) -> list[diag.Diagnostic]:
    seen: set[tuple] = set()
    result = []
    for item in items:
        key = (item.code, item.span)
        if key not in seen:
            seen.add(key)
            result.append(item)
    return result


def mixin_methods(model: Model) -> list[diag.Diagnostic]:
    """Mixins are entered only through assumeRole blocks; their non-plain methods never run."""
    found = []
    for symbol in model.roles.values():
        if not symbol.is_mixin:
            continue
        for method in symbol.methods.values():
            if method.owner == symbol.name and method.kind in (ast.MethodKind.STARTUP,
                                                                ast.MethodKind.BEHAVIOR):
                found.append(diag.make(
                    codes.MIXIN_METHOD_IGNORED, method.decl.name.span,
                    f"{method.kind.value} method '{method.name}' of mixin {symbol.name} is not "
                    "compiled for the DCD-VM: a mixin is only played inside an assumeRole block; "
                    "make it a plain method and call it there"))
    return found
