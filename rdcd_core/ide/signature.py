"""Signature help for Module API calls, from the one table."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.context import cursor_context
from rdcd_core.module_api import lookup_function, lookup_self


@dataclass(frozen=True)
class SignatureInfo:
    label: str
    doc: str
    parameters: tuple[tuple[int, int], ...]  # offsets of each parameter inside ``label``
    active_parameter: int


def signature_help(text: str, offset: int) -> SignatureInfo | None:
    call = cursor_context(text, offset).call
    if call is None or call.form == "global":
        return None
    primitive = lookup_self(call.callee) if call.form == "self" else lookup_function(call.callee)
    if primitive is None:
        return None
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
