"""Completion from the text around the cursor and the last model that was good enough."""

from __future__ import annotations

import re
from dataclasses import dataclass

from rdcd_core.ide.context import (
    CursorContext,
    after_values,
    assume_role_blocks,
    cursor_context,
    enclosing_parameters,
    in_deployment,
    previous_word,
    role_tail,
)
from rdcd_core.module_api import FUNCTIONS, SELF_PRIMITIVES, Primitive, lookup_function, lookup_self
from rdcd_core.semantics.model import Model, RoleKind
from rdcd_core.types import PREDEFINED_VALUES, Type


@dataclass(frozen=True)
class CompletionItem:
    label: str
    kind: str  # role, mixin, constant, state, parameter, method, command, primitive, function,
    # predefined, keyword
    detail: str = ""
    insert_text: str | None = None  # a snippet when set
    documentation: str = ""


Items = list[CompletionItem]
MEMBER_START_KEYWORDS = ("abstract", "constant", "state", "startup", "behavior", "command", "self", "if")
TOP_KEYWORDS = ("abstract", "role", "state", "travelling", "deployment")
AGGREGATES = ("min", "max", "count", "sum")
STATE_NAME = re.compile(r"\bstate\s+\Z")
INITIAL_VALUE = re.compile(r"\bstate\s+[A-Za-z_]\w*\s*:=[^;{}]*\Z")  # a constant int: no state


def complete(text: str, offset: int, model: Model | None) -> tuple[int, list[CompletionItem]]:
    """The offset where the completed word starts, and the items (filtered by the typed prefix)."""
    context = cursor_context(text, offset)
    items = _items(context, model)
    prefix = context.prefix.lower()
    return context.start, [item for item in items if item.label.lower().startswith(prefix)]


def _items(context: CursorContext, model: Model | None) -> list[CompletionItem]:
    word = previous_word(context.before)
    if after_values(context.before):
        return module_state_items(model)
    if context.after_dot == "self":
        return self_members(context, model)
    if context.after_dot is not None:
        return commands_of(model, context.after_dot)
    if word in ("extends", "modifies"):
        return role_items(model, lambda kind: kind is not RoleKind.MIXIN)
    if in_deployment(context.before):
        listed = set(context.before[context.before.rfind("deployment"):].replace(",", " ").split())
        return [item for item in role_items(model, lambda kind: kind is RoleKind.CONCRETE)
                if item.label not in listed]
    if STATE_NAME.search(context.before[-200:]):
        return []  # naming a new state: nothing to offer
    if INITIAL_VALUE.search(context.before[-200:]):
        return constant_items(context, model, Type.INT) + predefined_items(Type.INT)
    call = context.call
    if call is not None:
        special = _argument_items(context, model)
        if special is not None:
            return special
    if context.role is None:
        return [CompletionItem(k, "keyword") for k in TOP_KEYWORDS]
    if _at_statement_start(context.before):
        return statement_items(context, model)
    return expression_items(context, model, compared_type(context, model))


COMPARED = re.compile(r"(self\s*\.\s*)?([A-Za-z_]\w*)\s*(\(\s*\))?\s*(==|!=)\s*\Z")


def compared_type(context: CursorContext, model: Model | None) -> Type | None:
    """After ``left ==`` or ``left !=``: the type of ``left`` when it is a name or a query."""
    match = COMPARED.search(context.before[-200:])
    if match is None:
        return None
    name = match.group(2)
    if match.group(1):
        primitive = lookup_self(name)
        return primitive.result if primitive is not None else None
    if name in PREDEFINED_VALUES:
        return PREDEFINED_VALUES[name].type
    for role in _visible_roles(context, model):
        assert model is not None
        constant = model.roles[role].constants.get(name)
        if constant is not None and constant.value is not None:
            return constant.value.type
        if name in model.roles[role].states:
            return Type.INT
    if model is not None and name in model.states or name in enclosing_parameters(context.before):
        return Type.INT
    return None


def _at_statement_start(before: str) -> bool:
    stripped = before.rstrip()
    return not stripped or stripped[-1] in "{};"


def _argument_items(context: CursorContext, model: Model | None) -> list[CompletionItem] | None:
    call = context.call
    assert call is not None
    if call.form == "self" and call.callee == "assumeRole" and call.arg_index == 0:
        return mixin_items(model, context.role)
    if call.form == "function" and call.callee == "connected_role" and call.arg_index == 1:
        return role_items(model, lambda kind: True)
    if call.form == "function" and call.callee == "neighbours":
        return predefined_items(Type.DIR)  # or a connector number 0..7
    if call.form == "function" and call.callee in AGGREGATES and call.arg_index == 0:
        values = [CompletionItem("neighbours", "keyword", "the neighbours' values of a module state",
                                 "neighbours.", "`neighbours.s`, `neighbours(DOWN).s`, `neighbours(3).s`"),
                  CompletionItem("children", "keyword", "the children's values of a module state",
                                 "children.", "`children.s`: the neighbours whose parent is this module")]
        if call.callee in ("count", "sum"):
            return values
        return values + expression_items(context, model, Type.INT)
    primitive = lookup_self(call.callee) if call.form == "self" else lookup_function(call.callee)
    if primitive is None or call.arg_index >= len(primitive.params):
        return None
    expected = primitive.params[call.arg_index].type
    if expected is Type.BLOCK:
        return []
    return expression_items(context, model, expected)


# -- item builders --------------------------------------------------------------------------------
def primitive_item(primitive: Primitive) -> CompletionItem:
    if primitive.is_query:
        snippet = primitive.name
    else:
        args = ", ".join(f"${{{i + 1}:{p.name}}}" for i, p in enumerate(primitive.params))
        snippet = f"{primitive.name}({args})"
    kind = "primitive" if primitive.name in SELF_PRIMITIVES else "function"
    return CompletionItem(primitive.name, kind, primitive.signature, snippet, primitive.doc)


def self_members(context: CursorContext, model: Model | None) -> list[CompletionItem]:
    items = [primitive_item(p) for p in SELF_PRIMITIVES.values()]
    for role in _visible_roles(context, model):
        symbol = model.roles[role] if model is not None else None
        if symbol is None:
            continue
        for method in symbol.methods.values():
            if method.kind == "plain" and all(i.label != method.name for i in items):
                items.append(CompletionItem(method.name, "method", f"method of {method.owner}",
                                            call_snippet(method.name, method.decl.params)))
    return items


def call_snippet(name: str, params: tuple) -> str:  # type: ignore[type-arg]
    args = ", ".join(f"${{{i + 1}:{p.text}}}" for i, p in enumerate(params))
    return f"{name}({args})"


def _visible_roles(context: CursorContext, model: Model | None) -> list[str]:
    if model is None or context.role is None or context.role not in model.roles:
        return []
    roles = [context.role]
    if context.role_modifies:
        roles.append(context.role_modifies)
    tail = role_tail(context.before)
    roles = [m for m in reversed(assume_role_blocks(tail)) if m in model.roles] + roles
    return roles


def commands_of(model: Model | None, role: str) -> list[CompletionItem]:
    if model is None or role not in model.roles:
        return []
    return [CompletionItem(m.name, "command", f"command of {m.owner}", call_snippet(m.name, m.decl.params))
            for m in model.roles[role].methods.values() if m.kind == "command"]


def module_state_items(model: Model | None) -> list[CompletionItem]:
    """After ``neighbours.`` or ``children.``: neighbours publish module state only."""
    if model is None:
        return []
    return [CompletionItem(s.name, "state", f"module state := {s.initial}") for s in model.states.values()]


def state_items(context: CursorContext, model: Model | None) -> list[CompletionItem]:
    """The parameters of the enclosing method, the role's state, then module state (innermost first,
    as names resolve)."""
    items = [CompletionItem(p, "parameter", "parameter") for p in enclosing_parameters(context.before)]
    if model is None:
        return items
    for role in _visible_roles(context, model):
        for state in model.roles[role].states.values():
            detail = f"role state of {state.owner} := {state.initial}"
            items.append(CompletionItem(state.name, "state", detail))
    items += [CompletionItem(s.name, "state", f"module state := {s.initial}") for s in model.states.values()]
    return items


def role_items(model: Model | None, accept) -> list[CompletionItem]:  # type: ignore[no-untyped-def]
    if model is None:
        return []
    return [CompletionItem(name, "mixin" if symbol.is_mixin else "role", f"{symbol.kind.value} role")
            for name, symbol in model.roles.items() if symbol.decl is not None and accept(symbol.kind)]


def mixin_items(model: Model | None, role: str | None) -> list[CompletionItem]:
    if model is None:
        return []
    if role is not None and role in model.roles:
        names = model.mixins_of(role)
    else:
        names = [r for r, s in model.roles.items() if s.is_mixin]
    return [CompletionItem(n, "mixin", f"mixin modifying {model.roles[n].modifies}") for n in names]


def constant_items(context: CursorContext, model: Model | None, expected: Type | None) -> Items:
    items: list[CompletionItem] = []
    for role in _visible_roles(context, model):
        assert model is not None
        for constant in model.roles[role].constants.values():
            constant_type = constant.value.type if constant.value is not None else None
            if expected is not None and constant_type is not None and constant_type is not expected:
                continue
            if all(i.label != constant.name for i in items):
                detail = f"constant of {constant.owner}"
                items.append(CompletionItem(constant.name, "constant", detail))
    return items


def predefined_items(expected: Type | None) -> list[CompletionItem]:
    return [CompletionItem(v.name, "predefined", f"{v.type.value} = {v.code}", None, v.doc)
            for v in PREDEFINED_VALUES.values() if expected is None or v.type is expected]


def expression_items(context: CursorContext, model: Model | None, expected: Type | None) -> Items:
    items = state_items(context, model) if expected in (None, Type.INT) else []
    items += constant_items(context, model, expected) + predefined_items(expected)
    if expected in (None, Type.INT):
        items += [primitive_item(f) for f in FUNCTIONS.values() if expected is None or f.result is expected]
    if expected is None:
        items.append(CompletionItem("self", "keyword"))
    if expected is Type.ROLE:
        items += role_items(model, lambda kind: True)
    return _unique(items)


def statement_items(context: CursorContext, model: Model | None) -> list[CompletionItem]:
    items = [CompletionItem(k, "keyword") for k in MEMBER_START_KEYWORDS]
    items += expression_items(context, model, None)
    items += role_items(model, lambda kind: kind is not RoleKind.MIXIN)
    return _unique(items)


def _unique(items: Items) -> Items:
    """The first item of each label (an inner name hides an outer one)."""
    seen: set[str] = set()
    unique = []
    for item in items:
        if item.label not in seen:
            seen.add(item.label)
            unique.append(item)
    return unique

