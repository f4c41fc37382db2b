"""The RDCD compiler: checked Model -> DCD-VM fragments, role table and injection plan.

Phases (one module each): copy-down (done by semantics; ``context`` resolves members per
concrete role, mixins overlaid inside ``assumeRole``), ``roletable``, ``discovery``, ``entry``
(startup, commands, behaviours), ``exprgen``/``stmtgen`` (code with constants folded per concrete
role, plain methods inlined), ``peephole``, ``layout``, ``plan`` (splitting and injection).
"""

from __future__ import annotations

import dataclasses

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes  # noqa: F401  (registers the diagnostic codes)
from rdcd_core.compiler.chain import spare_numbers
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.discovery import invariants, role_mask
from rdcd_core.compiler.early import early_commands
from rdcd_core.compiler.entry import assign_command_numbers
from rdcd_core.compiler.ir import Ins, Item
from rdcd_core.compiler.limits import command_limit, mixin_methods, program_limit
from rdcd_core.compiler.lowering import axis_states
from rdcd_core.compiler.plan import plan
from rdcd_core.compiler.program import (
    DEFAULT_PACKET_BUDGET,
    HEADER_BYTES,
    MAX_PROGRAM_BYTES,  # noqa: F401  (part of the package's interface)
    CompiledProgram,
    Fragment,
    RoleEntry,
    StateEntry,
)
from rdcd_core.compiler.roletable import build_role_table
from rdcd_core.compiler.verify import verify_fragments
from rdcd_core.semantics.model import Model, StateSymbol
from rdcd_core.source import LineIndex
from vm.isa.opcodes import DATA_OPCODE
from vm.isa.targets import DEFAULT, ORIGINAL, TARGETS, Target

__all__ = ["TARGETS", "CompiledProgram", "Fragment", "RoleEntry", "add_source_lines",
           "compile_model", "resolve_target", "target_diagnostics"]


UNSENDABLE = "W601"  # a fragment over the packet budget that could not be split


def _compact_runs(target: Target) -> bool:
    """Whether ``target`` runs the compact form of sequences: its tables and its one action."""
    return target.implements_name("TABLE") and target.implements_name("ACT")


def compile_model(model: Model, *, packet_budget: int = DEFAULT_PACKET_BUDGET, strict_isa: bool = False,
                  text: str | None = None, target: Target | str | None = None,
                  reverse: str | None = None, compact: bool = False) -> CompiledProgram:
    """Compiles a checked model for ``target`` (a ``vm.isa.targets`` description or its name;
    default: this project's VM; ``strict_isa`` is the old name of the original target). With
    errors in the model, returns an empty program.

    ``diagnostics`` holds the compiler's own (E6xx/W6xx), not the model's. Pass the source
    ``text`` to get line numbers in the source maps. ``reverse``: the name of a sequence to
    compile backwards (the undo of each step, in reverse order).
    """
    chosen = resolve_target(target, strict_isa)
    if model.has_errors:
        return CompiledProgram([], [], [], packet_budget, target=chosen.name)
    if model.program.sequences:  # compiled as state and behaviours (rdcd_core/sequences/lower.py)
        from rdcd_core.sequences.lower import lowered_model

        original = model
        model = lowered_model(model, reverse, compact)
        why_not_tables = ""
        if model.has_errors and not compact and _compact_runs(chosen):
            tables = lowered_model(original, reverse, True)  # too many behaviours for a role (E121)?
            if not tables.has_errors:
                smaller = compile_model(original, packet_budget=packet_budget, target=chosen, text=text,
                                        reverse=reverse, compact=True)
                unfit = [d for d in smaller.diagnostics
                         if d.severity is diag.Severity.ERROR or d.code == UNSENDABLE]
                if smaller.fragments and not unfit:
                    return smaller
                # the error is the ordinary form's, which the program is written in; the tables'
                # own failure (a fragment of the compiler's making) says why they did not help
                why_not_tables = (f"; the steps as tables (the compact form) do not fit either "
                                  f"({unfit[0].code}: {unfit[0].message.split(';')[0]})" if unfit else "")
        if model.has_errors:
            errors = [dataclasses.replace(d, message=d.message + why_not_tables)
                      for d in model.diagnostics if d.severity is diag.Severity.ERROR]
            return CompiledProgram([], [], [], packet_budget, errors, target=chosen.name)
    table = build_role_table(model)
    commands = assign_command_numbers(model)
    found = command_limit(model, commands)  # role ids: the checker's E120 counts the table's
    ctxs = {role: Context(model, table, role, command_numbers=commands, target=chosen)
            for role in model.deployment}
    for ctx in ctxs.values():  # a role's code runs on the axes its invariants allow
        ctx.states = axis_states(model, ctx.role, role_mask(invariants(ctx), ctx, local_only=True))
    # a fragment must fit its packet and a program slot, however large the packets may be
    prologue = _state_prologue(model, ctxs)
    travelling = next((s for s in model.states.values() if s.travelling), None)
    trailer = bytes((DATA_OPCODE, travelling.initial & 0xFF)) if travelling is not None else b""
    planner = plan(ctxs, model.deployment, min(packet_budget - HEADER_BYTES, chosen.slot_bytes), prologue,
                   trailer, spare_numbers(model, commands), commands)
    for ctx in ctxs.values():
        found.extend(ctx.diagnostics)
    found.extend(planner.diagnostics)
    if chosen.quirks.firmware_controller:  # the firmware drops a command it has no code for
        found.extend(early_commands(planner.traffic, table.entries, chosen.name))
    found.extend(program_limit(model, chosen.program_slots))
    if model.program.sequences:  # fragments a module keeps while they spread (E805)
        from rdcd_core.sequences.limits import slot_limit

        over = slot_limit(model, planner.fragments, chosen.program_slots)
        # a fragment over the packet budget is only a warning (W601), but the robot never gets it
        failed = over or any(d.severity is diag.Severity.ERROR or d.code == UNSENDABLE for d in found)
        if failed and not compact and _compact_runs(chosen):
            # too many fragments, or too large: the steps as tables (rdcd_core/sequences/compact.py),
            # kept if that compiles and sends; a program that does keeps its ordinary form, byte
            # for byte
            smaller = compile_model(original, packet_budget=packet_budget, target=chosen, text=text,
                                    reverse=reverse, compact=True)
            if smaller.fragments and not smaller.has_errors and \
                    not any(d.code == UNSENDABLE for d in smaller.diagnostics):
                return smaller
        found.extend(over)
    found.extend(mixin_methods(model))
    if not any(d.severity is diag.Severity.ERROR for d in found):  # errors make bad code
        found.extend(verify_fragments(planner.fragments, chosen))
    if text is not None:
        add_source_lines(planner.fragments, LineIndex(text))
    names = [f.name for f in planner.fragments]
    states = [StateEntry(s.name, s.index, s.initial, s.owner, s.published, _holders(model, s, table.entries))
              for s in sorted(model.all_states(), key=lambda s: s.index)]
    return CompiledProgram(planner.fragments, table.entries, names, packet_budget, _dedupe(found),
                           target=chosen.name, states=states)


def _holders(model: Model, state: StateSymbol, entries: list) -> tuple[str, ...]:
    """The roles that have a role state: its owner, the roles extending it and the applications of a
    mixin to one of them (``assumeRole`` keeps the base role's state); () for module state."""
    if state.owner is None:
        return ()
    names = {r.name for r in model.roles.values() if r.states.get(state.name) is state}
    ids = {e.id for e in entries if e.name in names}
    names.update(e.name for e in entries if ids & set(e.instance_of))
    return tuple(sorted(names))


def _state_prologue(model: Model, ctxs: dict[str, Context]) -> list[Item]:
    """Module state that does not start at 0 gets its initial value first thing, in the first
    fragment every module runs (nothing when no module state needs it)."""
    code: list[Item] = []
    first = next(iter(ctxs.values()), None)
    for state in model.states.values():
        if state.travelling and first is not None:  # the value the program brought (DATA)
            code.append(Ins("LOAD_DATA", (), state.decl.span))
            first.need("LOAD_DATA", state.decl.span, "a travelling state needs the extension instruction")
            code.append(Ins("STORE_STATE", (state.index,), state.decl.span))
            continue
        if state.initial == 0 or first is None:
            continue
        code.append(Ins("PUSH", (state.initial,), state.decl.span))
        first.need("STORE_STATE", state.decl.span, "state needs the extension instruction")
        code.append(Ins("STORE_STATE", (state.index,), state.decl.span))
    return code


def resolve_target(target: Target | str | None, strict_isa: bool = False) -> Target:
    """The target description for a name (``TARGETS``), a description, or None (``strict_isa``:
    the original firmware, the only target that refuses the extensions). Unknown names raise
    ValueError; the CLI offers only known ones."""
    if isinstance(target, Target):
        return target
    if target is None:
        return ORIGINAL if strict_isa else DEFAULT
    if target not in TARGETS:
        raise ValueError(f"unknown target {target!r}; known: {', '.join(TARGETS)}")
    return TARGETS[target]


def target_diagnostics(model: Model, packet_budget: int = DEFAULT_PACKET_BUDGET,
                       target: Target | str | None = None) -> list[diag.Diagnostic]:
    """The §6 target limits of ``model`` (empty when the model has errors)."""
    if model.has_errors:
        return []
    return compile_model(model, packet_budget=packet_budget, target=target).diagnostics


def add_source_lines(fragments: list[Fragment], index: LineIndex) -> None:
    """Give each fragment's source map, and the fragment, the lines of ``index``'s text they come from."""
    for fragment in fragments:
        fragment.source_map = [
            type(e)(e.offset, e.size, e.span, index.line_col(e.span.start).line + 1 if e.span else 0)
            for e in fragment.source_map]
        lines = [entry.line for entry in fragment.source_map if entry.line]
        if fragment.span is not None:
            lines += [index.line_col(fragment.span.start).line + 1]
        if lines:
            fragment.source = (min(lines), max(lines))


def _dedupe(items: list[diag.Diagnostic]) -> list[diag.Diagnostic]:
    seen: set[tuple] = set()
    result = []
    for item in items:
        key = (item.code, item.span.start, item.span.end, item.message)
        if key not in seen:
            seen.add(key)
            result.append(item)
    return sorted(result, key=lambda d: (d.span.start, d.code))
