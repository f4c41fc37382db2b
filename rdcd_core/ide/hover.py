"""Hover: markdown about the name under the cursor, read from the model and the Module API table."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.fragments import sizes_of_method, sizes_of_role
from rdcd_core.ide.hover_state import keyword_hover, parameter_hover, state_hover
from rdcd_core.ide.navigation import member_chain, split_target
from rdcd_core.ide.states import signature_text
from rdcd_core.module_api import lookup_function, lookup_self
from rdcd_core.semantics.model import Model, RoleKind, Value
from rdcd_core.source import Span
from rdcd_core.types import PREDEFINED_VALUES, Type


@dataclass(frozen=True)
class HoverResult:
    markdown: str
    span: Span


def describe_value(model: Model | None, value: Value | None) -> str:
    if value is None:
        return "(not a constant value)"
    if value.type in (Type.AXIS, Type.DIR, Type.EVENT):
        for predefined in PREDEFINED_VALUES.values():
            if predefined.type is value.type and predefined.code == value.value:
                return predefined.name
    return str(value.value)


def hover(analysis: Analysis, offset: int) -> HoverResult | None:
    step = step_hover(analysis, offset)
    if step is not None:
        return step
    ref = analysis.reference_at(offset)
    model = analysis.model
    if ref is None:
        keyword = keyword_hover(analysis, offset)
        return HoverResult(*keyword) if keyword is not None else None
    if model is None:
        return None
    text = None
    if ref.kind == "role":
        text = role_hover(analysis, ref.target)
    elif ref.kind == "constant":
        text = constant_hover(model, ref.target)
    elif ref.kind in ("method", "command"):
        text = method_hover(analysis, ref.target)
    elif ref.kind == "primitive":
        text = primitive_hover(ref.target)
    elif ref.kind == "predefined":
        text = predefined_hover(ref.target)
    elif ref.kind == "state":
        text = state_hover(analysis, ref.target)
    elif ref.kind == "parameter":
        text = parameter_hover(analysis, ref.target)
    return HoverResult(text, ref.name.span) if text else None


def step_hover(analysis: Analysis, offset: int) -> HoverResult | None:
    """On a sequence's step: which module acts and the structure after it, as the checker's run
    through the lattice model found them (docs/reconfiguration.md)."""
    if analysis.program is None:
        return None
    for index, sequence in enumerate(analysis.program.sequences):
        if not sequence.span.contains(offset):
            continue
        steps = [s for item in sequence.items
                 for s in ((item,) if not hasattr(item, "steps") else item.steps)]
        step = next((s for s in steps if s.span.contains(offset)), None)
        if step is None:
            return None
        trace = analysis.traces.get(index)
        if trace is None:
            text = ("Step of sequence `" + sequence.name.text + "`: no starting configuration to run "
                    "it on (name one: `sequence " + sequence.name.text + "(car7) { … }`).")
            return HoverResult(text, step.span)
        result = next((r for r in trace.results if r.step is step), None)
        if result is None:
            return HoverResult("Step of sequence `" + sequence.name.text + "`: not reached by the "
                               "check (an earlier step cannot happen).", step.span)
        text = (f"Step {steps.index(step) + 1} of `{sequence.name.text}`: module {result.module} "
                f"acts. The structure after it:\n\n```text\n{result.after}\n```")
        return HoverResult(text, step.span)
    return None


def role_hover(analysis: Analysis, name: str) -> str | None:
    model = analysis.model
    assert model is not None
    symbol = model.roles.get(name)
    if symbol is None:
        return None
    kind = {RoleKind.CONCRETE: "role", RoleKind.ABSTRACT: "abstract role", RoleKind.MIXIN: "mixin role"}
    lines = [f"**{kind[symbol.kind]}** `{name}`", ""]
    if symbol.is_mixin:
        lines.append(f"modifies `{symbol.modifies}`")
    else:
        lines.append("chain: " + " → ".join(f"`{r}`" for r in model.ancestors(name)))
    subs = [r for r in model.subroles(name) if r != name]
    if subs:
        lines.append("sub-roles: " + ", ".join(f"`{r}`" for r in subs))
    if not symbol.is_mixin:
        mixins = model.mixins_of(name)
        if mixins:
            lines.append("mixins: " + ", ".join(f"`{m}`" for m in mixins))
    members = []
    for constant in symbol.constants.values():
        value = "abstract" if constant.definition is None else describe_value(model, constant.value)
        members.append(f"- constant `{constant.name}` = {value} — from `{constant.owner}`")
    for method in symbol.methods.values():
        prefix = "abstract " if method.is_abstract else ""
        kind_word = "" if method.kind == "plain" else f"{method.kind} "
        members.append(f"- {prefix}{kind_word}`{method.name}()` — from `{method.owner}`")
    if symbol.invariants:
        members.append(f"- {len(symbol.invariants)} invariant(s)")
    if members:
        lines += ["", "members:"] + members
    sizes = sizes_of_role(analysis, model.concrete_subroles(name) or [name])
    if sizes:
        budget = analysis.compiled().program_budget
        lines += ["", f"fragments (program budget {budget} B):"]
        for fragment in sizes:
            mark = " ⚠ over budget" if fragment.over(budget) else ""
            lines.append(f"- `{fragment.name}` ({fragment.kind}): {fragment.size} B{mark}")
    return "\n".join(lines)


def constant_hover(model: Model, target: str) -> str | None:
    role, name = split_target(target)
    lines = [f"**constant** `{name}`", ""]
    family = set()
    for ancestor in member_chain(model, role):
        family.update(model.subroles(ancestor))
    rows = []
    for candidate in sorted(family):
        symbol = model.roles.get(candidate)
        if symbol is None or symbol.kind is not RoleKind.CONCRETE or name not in symbol.constants:
            continue
        constant = symbol.constants[name]
        rows.append(f"- `{candidate}`: {describe_value(model, constant.value)} (from `{constant.owner}`)")
    owner = model.roles.get(role)
    if owner is not None and name in owner.constants:
        constant = owner.constants[name]
        declared = "abstract" if constant.definition is None else describe_value(model, constant.value)
        lines.append(f"in `{role}`: {declared} (declared in `{constant.owner}`)")
    if rows:
        lines += ["", "value in each concrete role:"] + rows
    return "\n".join(lines)


def method_hover(analysis: Analysis, target: str) -> str | None:
    model = analysis.model
    assert model is not None
    role, name = split_target(target)
    symbol = model.roles.get(role)
    method = symbol.methods.get(name) if symbol is not None else None
    if method is None:
        return None
    prefix = "abstract " if method.is_abstract else ""
    kind = "method" if method.kind == "plain" else f"{method.kind} method"
    lines = [f"**{prefix}{kind}** `{role}.{signature_text(method.decl)}`", "",
             f"declared in `{method.owner}`"]
    overriders = [r for r in model.subroles(role)
                  if r != role and name in model.roles[r].methods and model.roles[r].methods[name].owner == r]
    if overriders:
        lines.append("overridden in: " + ", ".join(f"`{r}`" for r in overriders))
    if method.kind == "command":
        call = f"{role}.{name}({', '.join(p.text for p in method.decl.params)})"
        lines.append(f"runs on every module playing `{role}` or a sub-role when called as `{call}`")
    sizes = sizes_of_method(analysis, model.concrete_subroles(role) or [role], name)
    if sizes:
        budget = analysis.compiled().program_budget
        lines += ["", "fragments:"]
        for fragment in sizes:
            mark = " ⚠ over budget" if fragment.over(budget) else ""
            lines.append(f"- `{fragment.name}`: {fragment.size} B{mark}")
    return "\n".join(lines)


def primitive_hover(name: str) -> str | None:
    primitive = lookup_self(name) or lookup_function(name)
    if primitive is None:
        return None
    signatures = primitive.signature
    if primitive.aggregate:
        signatures += f"\n{primitive.name}(v: values) -> {primitive.result.value}"
    runtime = ""
    if primitive.runtime_op is not None:  # issue 25: a computed argument
        checked = " and a value out of range is a runtime error" if primitive.values else ""
        runtime = (f"\n\nThe argument may be computed: on the default target `{primitive.runtime_op}` "
                   f"takes it at run time{checked}.")
    return f"```rdcd\n{signatures}\n```\n\n{primitive.doc}{runtime}\n\n*Module API*"


def predefined_hover(name: str) -> str | None:
    value = PREDEFINED_VALUES.get(name)
    if value is None:
        return None
    return (f"**{value.type.value}** `{name}`\n\n{value.doc}\n\n"
            f"encoding: `{value.code}` (0x{value.code:02x})")
