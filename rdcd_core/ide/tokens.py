"""Semantic tokens: resolved names from the model; keywords, numbers and comments from the lexer."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.states import assignment_starts
from rdcd_core.semantics.model import RoleKind
from rdcd_core.source import Span
from rdcd_core.syntax.tables import tables

# New entries go at the end: clients cache the legend's indices and bits.
TOKEN_TYPES = ("class", "interface", "variable", "method", "function", "enumMember", "keyword",
               "number", "comment", "operator", "parameter")
# A constant is a readonly variable; a state a variable that is not (module state also "static":
# it outlives role changes); an assignment's target carries "modification".
TOKEN_MODIFIERS = ("declaration", "readonly", "abstract", "defaultLibrary", "static", "modification")


@dataclass(frozen=True)
class Token:
    span: Span
    type: str
    modifiers: tuple[str, ...] = ()


def _ref_token(analysis: Analysis, kind: str, target: str, definition: bool,
               written: bool = False) -> tuple[str, tuple[str, ...]]:
    modifiers: list[str] = ["declaration"] if definition else []
    model = analysis.model
    if kind == "role":
        symbol = model.roles.get(target) if model is not None else None
        if symbol is not None and symbol.is_mixin:
            return "interface", tuple(modifiers)
        if symbol is not None and symbol.kind is RoleKind.ABSTRACT:
            modifiers.append("abstract")
        if symbol is not None and symbol.decl is None:
            modifiers.append("defaultLibrary")
        return "class", tuple(modifiers)
    if kind == "constant":
        return "variable", tuple(modifiers + ["readonly"])
    if kind in ("method", "command"):
        return "method", tuple(modifiers)
    if kind == "state":
        if "." not in target:
            modifiers.append("static")
        if written:
            modifiers.append("modification")
        return "variable", tuple(modifiers)
    if kind == "parameter":
        return "parameter", tuple(modifiers + ["readonly"])
    if kind == "primitive":
        return "function", ("defaultLibrary",)
    return "enumMember", ("readonly", "defaultLibrary")


def semantic_tokens(analysis: Analysis) -> list[Token]:
    """Tokens in text order, read from the parser's own lexer (one set of lexical rules)."""
    refs = {(r.name.span.start, r.name.span.end): r for r in analysis.references()}
    writes = assignment_starts(analysis)
    lexer = tables().lexer
    lexed = lexer.lex(analysis.text)
    found = [Token(comment.span, "comment") for comment in lexed.comments]
    for tok in lexed.tokens:
        if tok.type == "NAME":
            ref = refs.get((tok.start, tok.end))
            if ref is not None:
                token_type, modifiers = _ref_token(analysis, ref.kind, ref.target, ref.is_definition,
                                                   tok.start in writes)
                found.append(Token(Span(tok.start, tok.end), token_type, modifiers))
        elif tok.type == "INT":
            found.append(Token(Span(tok.start, tok.end), "number"))
        elif tok.value in lexer.keywords:
            found.append(Token(Span(tok.start, tok.end), "keyword"))
    found.sort(key=lambda token: token.span.start)
    return found
