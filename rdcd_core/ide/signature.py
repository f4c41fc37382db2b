"""Signature help for Module API calls (from the one table), for commands with arguments
(``Wheel.turn(``) and for the role's own methods with parameters (``self.helper(``)."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.context import CallContext, cursor_context
from rdcd_core.module_api import lookup_function, lookup_self
from rdcd_core.semantics.model import MethodSymbol, Model


@dataclass(frozen=True)
class SignatureInfo:
    label: str
    doc: str
    parameters: tuple[tuple[int, int], ...]  # offsets of each parameter inside ``label``
    active_parameter: int


_WHERE = "where: dir | connector 0..7"
NEIGHBOURS = SignatureInfo(
    f"neighbours({_WHERE}).s",
    "The values of module state s published by the neighbours on the connectors facing a direction "
    "(UP, EAST, …), or by the neighbour on one connector; an argument of min, max, count or sum.",
    ((len("neighbours("), len("neighbours(") + len(_WHERE)),), 0)


def signature_help(text: str, offset: int, model: Model | None = None) -> SignatureInfo | None:
    """``model`` (the last good one) is needed only for the program's own methods and commands."""
    context = cursor_context(text, offset)
    call = context.call
    if call is None:
        return None
    if call.form == "function" and call.callee == "neighbours":
        return NEIGHBOURS
    primitive = None
    if call.form == "self":
        primitive = lookup_self(call.callee)
    elif call.form == "function":
        primitive = lookup_function(call.callee)
    if primitive is None:
        return _program_method(model, call, context.role, context.role_modifies)
    label = primitive.signature
    spans = []
    position = label.index("(") + 1
    for param in primitive.params:
        piece = f"{param.name}: {param.type.value}"
        start = label.index(piece, position)
        spans.append((start, start + len(piece)))
        position = start + len(piece)
    active = min(call.arg_index, max(len(primitive.params) - 1, 0))
    return SignatureInfo(label, primitive.doc, tuple(spans), active)


def _find_method(model: Model, call: CallContext, role: str | None,
                 modifies: str | None) -> MethodSymbol | None:
    if call.form == "global":
        symbol = model.roles.get(call.qualifier or "")
        method = symbol.methods.get(call.callee) if symbol is not None else None
        return method if method is not None and method.kind == "command" else None
    if call.form != "self":
        return None
    for name in (role, modifies):
        symbol = model.roles.get(name or "")
        method = symbol.methods.get(call.callee) if symbol is not None else None
        if method is not None and method.kind == "plain":
            return method
    return None


def _program_method(model: Model | None, call: CallContext, role: str | None,
                    modifies: str | None) -> SignatureInfo | None:
    if model is None:
        return None
    method = _find_method(model, call, role, modifies)
    if method is None:
        return None
    params = method.decl.params
    head = f"{call.qualifier}.{call.callee}(" if call.form == "global" else f"self.{call.callee}("
    spans = []
    label = head
    for index, param in enumerate(params):
        if index:
            label += ", "
        piece = f"{param.text}: int"
        spans.append((len(label), len(label) + len(piece)))
        label += piece
    label += ")"
    if call.form == "global":
        doc = (f"command of `{method.owner}`: runs on every module playing `{call.qualifier}` or a "
               "sub-role" + ("; the argument travels in the command packet's argument byte"
                             if params else ""))
    else:
        doc = f"method of `{method.owner}`" + ("; each call substitutes its arguments" if params else "")
    active = min(call.arg_index, max(len(params) - 1, 0))
    return SignatureInfo(label, doc, tuple(spans), active)
