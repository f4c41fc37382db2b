"""Limits of language.md §6 that need the compiler's view: role ids, command tables, slots."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.entry import behaviour_numbers, methods_of
from rdcd_core.compiler.roletable import RoleTable
from rdcd_core.semantics.model import Model
from rdcd_core.syntax import ast
from vm.isa.opcodes import PROGRAM_SLOTS, ROLE_IDS, USER_COMMANDS


def role_id_limit(model: Model, table: RoleTable) -> list[diag.Diagnostic]:
    if len(table.entries) <= ROLE_IDS:
        return []
    entry = table.entries[ROLE_IDS]
    decl = model.roles[entry.name.split("@")[0]].decl
    span = decl.name.span if decl else model.program.span
    return [diag.make(codes.TOO_MANY_ROLE_IDS, span,
                      f"the program needs {len(table.entries)} role ids after mixin expansion, "
                      f"the DCD-VM has {ROLE_IDS}; '{entry.name}' is number {entry.id}")]


def command_limit(model: Model, commands: dict[str, int]) -> list[diag.Diagnostic]:
    found: list[diag.Diagnostic] = []
    for role in model.deployment:
        methods = methods_of(model, role, ast.MethodKind.COMMAND)
        numbers = {m.name: commands[m.name] for m in methods}
        numbers.update(behaviour_numbers(model, role, commands))
        everything = methods + methods_of(model, role, ast.MethodKind.BEHAVIOR)
        for method in everything:
            if numbers[method.name] >= USER_COMMANDS:
                found.append(diag.make(
                    codes.TOO_MANY_COMMANDS, method.decl.name.span,
                    f"role {role} needs more than {USER_COMMANDS} command-table entries "
                    f"(commands and behaviours); '{method.name}' does not fit"))
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
            for node in ast.walk(method.decl.body):
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
