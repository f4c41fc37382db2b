"""Hover: markdown about the name under the cursor, read from the model and the Module API table."""

from __future__ import annotations

import re
from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.fragments import sizes_of_method, sizes_of_role
from rdcd_core.ide.navigation import member_chain, split_target
from rdcd_core.ide.states import assigning_methods, parameter_info, signature_text, state_symbol
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


KEYWORD_DOCS = {
    "neighbours": (
        "**neighbours** — the values of a module state that this module's neighbours published\n\n"
        "- `neighbours.s`: from every neighbour\n"
        "- `neighbours(DOWN).s`: from the neighbours on the connectors facing a direction\n"
        "- `neighbours(3).s`: from the neighbour on connector 3 (0..7)\n\n"
        "Only as the argument of `min`, `max`, `count` or `sum`, and only for module state: "
        "a neighbour publishes its value on every change. A behaviour that reads it runs again "
        "when a value changes."),
    "children": (
        "**children** — the values of a module state that this module's children published: "
        "the neighbours whose parent in the structure's tree (rooted at the module where the "
        "program entered) is this module.\n\n"
        "`children.s`, only as the argument of `min`, `max`, `count` or `sum`, e.g. "
        "`sum(children.size)`."),
    "state": (
        "**state** `s := value;` — a variable of the module (an int, -128..127, arithmetic "
        "saturates).\n\n"
        "- at the top level: **module state**, kept across role changes; neighbours can read it "
        "(`neighbours.s`)\n"
        "- in a role: **role state**, back to its initial value whenever the module takes the "
        "role or a sub-role\n\n"
        "Assign it with `s := expression;`."),
}
WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def hover(analysis: Analysis, offset: int) -> HoverResult | None:
    ref = analysis.reference_at(offset)
    model = analysis.model
    if ref is None:
        return keyword_hover(analysis, offset)
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
    return f"```rdcd\n{signatures}\n```\n\n{primitive.doc}\n\n*Module API*"


def keyword_hover(analysis: Analysis, offset: int) -> HoverResult | None:
    """``neighbours``, ``children`` and ``state``: keywords, so they have no reference."""
    text = analysis.text
    start = offset
    while start > 0 and (text[start - 1].isalnum() or text[start - 1] == "_"):
        start -= 1
    match = WORD.match(text, start)
    if match is None or match.group(0) not in KEYWORD_DOCS or match.end() < offset:
        return None
    if not _is_keyword_token(analysis, match.start(), match.end()):
        return None  # inside a comment
    return HoverResult(KEYWORD_DOCS[match.group(0)], Span(match.start(), match.end()))


def _is_keyword_token(analysis: Analysis, start: int, end: int) -> bool:
    from rdcd_core.syntax.tables import tables

    starts = analysis.cache.get("keyword_starts")
    if starts is None:
        lexer = tables().lexer
        try:
            lexed = lexer.lex(analysis.text)
        except Exception:  # hover must never fail on broken text
            return False
        starts = {(t.start, t.end) for t in lexed.tokens if t.value in KEYWORD_DOCS}
        analysis.cache["keyword_starts"] = starts
    return (start, end) in starts


def state_hover(analysis: Analysis, target: str) -> str | None:
    model = analysis.model
    assert model is not None
    symbol = state_symbol(model, target)
    if symbol is None:
        return None
    name = symbol.name
    if symbol.owner is None:
        lines = [f"**module state** `{name}` := {symbol.initial}", "",
                 f"kept across role changes; {symbol.initial} when the program starts on the module"]
    else:
        family = [r for r in model.subroles(symbol.owner) if r != symbol.owner]
        takes = f"`{symbol.owner}`" + (" or a sub-role (" + ", ".join(f"`{r}`" for r in family) + ")"
                                       if family else "")
        lines = [f"**role state** `{name}` := {symbol.initial} of role `{symbol.owner}`", "",
                 f"back to {symbol.initial} whenever the module takes {takes}; inside "
                 "`self.assumeRole(M, …)` the module keeps its role's state"]
    if symbol.published:
        lines.append(f"published: neighbours read it (`neighbours.{name}`, `children.{name}`), "
                     "so every change is sent to them")
    elif symbol.owner is None:
        lines.append("not published: no neighbour reads it")
    writers = assigning_methods(analysis, target)
    lines.append("assigned in: " + (", ".join(f"`{w}()`" for w in writers) if writers else "nowhere"))
    if symbol.index >= 0:
        lines.append(f"byte {symbol.index} of the module's state memory")
    return "\n".join(lines)


def parameter_hover(analysis: Analysis, target: str) -> str | None:
    model = analysis.model
    assert model is not None
    info = parameter_info(model, target)
    if info is None:
        return None
    kind = info.method.kind
    where = f"`{info.role}.{signature_text(info.method)}`"
    if kind == "command":
        lines = [f"**parameter** `{info.name.text}`: int of command {where}", "",
                 f"the argument of `{info.role}.{info.method.name.text}(value)`, carried in the "
                 "command packet's argument byte"]
    else:
        lines = [f"**parameter** `{info.name.text}`: int of method {where}", "",
                 f"argument {info.index + 1} of `self.{info.method.name.text}(…)`; each call "
                 "substitutes its argument (a method is inlined)"]
    lines.append("not available in event handlers (they run later): copy it into a state")
    return "\n".join(lines)


def predefined_hover(name: str) -> str | None:
    value = PREDEFINED_VALUES.get(name)
    if value is None:
        return None
    return (f"**{value.type.value}** `{name}`\n\n{value.doc}\n\n"
            f"encoding: `{value.code}` (0x{value.code:02x})")
