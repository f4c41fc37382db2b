"""Semantic tokens: resolved names from the model, keywords, numbers and comments from the text."""

from __future__ import annotations

import re
from dataclasses import dataclass

from rdcd_core.ide.analysis import Analysis
from rdcd_core.source import Span
from rdcd_core.syntax.keywords import KEYWORDS

TOKEN_TYPES = ("class", "interface", "variable", "method", "function", "enumMember", "keyword",
               "number", "comment", "operator")
TOKEN_MODIFIERS = ("declaration", "readonly", "abstract", "defaultLibrary")

LEXEME = re.compile(r"//[^\n]*|/\*.*?(?:\*/|\Z)|[A-Za-z_][A-Za-z0-9_]*|\d+", re.DOTALL)
KEYWORD_SET = frozenset(KEYWORDS)


@dataclass(frozen=True)
class Token:
    span: Span
    type: str
    modifiers: tuple[str, ...] = ()


def _ref_token(analysis: Analysis, kind: str, target: str, definition: bool) -> tuple[str, tuple[str, ...]]:
    modifiers: list[str] = ["declaration"] if definition else []
    model = analysis.model
    if kind == "role":
        symbol = model.roles.get(target) if model is not None else None
        if symbol is not None and symbol.is_mixin:
            return "interface", tuple(modifiers)
        if symbol is not None and symbol.kind.value == "abstract":
            modifiers.append("abstract")
        if symbol is not None and symbol.decl is None:
            modifiers.append("defaultLibrary")
        return "class", tuple(modifiers)
    if kind == "constant":
        return "variable", tuple(modifiers + ["readonly"])
    if kind in ("method", "command"):
        return "method", tuple(modifiers)
    if kind == "primitive":
        return "function", ("defaultLibrary",)
    return "enumMember", ("readonly", "defaultLibrary")


def semantic_tokens(analysis: Analysis) -> list[Token]:
    refs = {(r.name.span.start, r.name.span.end): r for r in analysis.references()}
    tokens: list[Token] = []
    for match in LEXEME.finditer(analysis.text):
        start, end = match.span()
        lexeme = match.group(0)
        span = Span(start, end)
        if lexeme.startswith("/"):
            tokens.append(Token(span, "comment"))
        elif lexeme[0].isdigit():
            tokens.append(Token(span, "number"))
        elif lexeme in KEYWORD_SET:
            tokens.append(Token(span, "keyword"))
        elif (ref := refs.get((start, end))) is not None:
            token_type, modifiers = _ref_token(analysis, ref.kind, ref.target, ref.is_definition)
            tokens.append(Token(span, token_type, modifiers))
    return tokens
