"""The texts of the syntax diagnostics: what went wrong, where, and what the parser expected.

Each function returns ``(code, message, related)``; ``line`` turns an offset into a 1-based line.
"""

from __future__ import annotations

from collections.abc import Callable

from rdcd_core.diagnostics import Related
from rdcd_core.source import Span
from rdcd_core.syntax import context as ctx
from rdcd_core.syntax.codes import (
    E_AFTER_DEPLOYMENT,
    E_CHAINED_COMPARISON,
    E_ELSE_WITHOUT_IF,
    E_EXPECTED_NAME,
    E_MISSING_CLOSE,
    E_MISSING_SEMICOLON,
    E_OUTSIDE_ROLE,
    E_UNEXPECTED_EOF,
    E_UNEXPECTED_TOKEN,
    E_UNMATCHED_CLOSE,
)
from rdcd_core.syntax.lexer import Tok

Line = Callable[[int], int]
Message = tuple[str, str, tuple[Related, ...]]
# the text of a punctuation token (the ones the recovery makes up among them)
TEXT = {name: shown[1:-1] for name, shown in ctx.TOKEN_TEXT.items() if shown.startswith("'")}


def _opened_here(tok: Tok) -> tuple[Related, ...]:
    return (Related(Span(tok.start, tok.end), "opened here"),)


def inserted(values: list, tok: Tok, tokens: tuple[str, ...], line: Line) -> Message:
    """The parser mended the text by inserting ``tokens`` before ``tok``."""
    first = tokens[0]
    found = ctx.describe_token(tok)
    k = ctx.open_bracket(values)
    if first == "SEMI":
        return E_MISSING_SEMICOLON, f"expected ';' after {ctx.construct_name(values, k)}, found {found}", ()
    if first == "RPAR" and k >= 0 and values[k].type == "LPAR":
        paren = values[k]
        return (E_MISSING_CLOSE, f"expected ')' to close {ctx.paren_owner(values, k)} opened on line "
                f"{line(paren.start)}, found {found}", _opened_here(paren))
    if first == "RBRACE" and k >= 0 and values[k].type == "LBRACE":
        brace = values[k]
        return (E_MISSING_CLOSE, f"expected '}}' to close {ctx.brace_owner(values, k)} opened on line "
                f"{line(brace.start)}, found {found}", _opened_here(brace))
    role = ctx.role_header(values)
    if first == "LBRACE" and ctx.is_tok(values[-1] if values else None, ("RPAR",)):
        return E_UNEXPECTED_TOKEN, f"expected a body '{{ … }}' or ';' before {found}", ()
    if first == "LBRACE" and role is not None:
        return E_UNEXPECTED_TOKEN, f"expected '{{' to open the body of role '{role}', found {found}", ()
    if first == "COMMA" and k >= 0 and ctx.brace_owner(values, k) == "the deployment":
        return E_UNEXPECTED_TOKEN, f"expected ',' between the role names, found {found}", ()
    what = " ".join(f"'{TEXT[c]}'" for c in tokens)
    return E_UNEXPECTED_TOKEN, f"expected {what} before {found}", ()


def unexpected(values: list, tok: Tok, expected: set[str]) -> Message:
    """``tok`` cannot follow what the parser read; ``expected`` is what could."""
    found = ctx.describe_token(tok)
    k = ctx.open_bracket(values)
    prev = values[-1] if values else None
    opener = values[k].type if k >= 0 else ""
    if tok.type in ("RBRACE", "RPAR") and opener != ("LBRACE" if tok.type == "RBRACE" else "LPAR"):
        want = "{" if tok.type == "RBRACE" else "("
        message = f"unmatched '{tok.value}': there is no open '{want}' to close"
        if opener:
            message += f" here (the innermost open bracket is a '{values[k].value}')"
        return E_UNMATCHED_CLOSE, message, ()
    if expected and expected <= {"NAME"}:
        after = f" after '{prev.value}'" if isinstance(prev, Tok) and prev.value else ""
        return E_EXPECTED_NAME, f"expected {ctx.name_kind(values)} name{after}, found {found}", ()
    if tok.value in ("<", ">", "<=", ">=") and ctx.after_comparison(values):
        return (E_CHAINED_COMPARISON,
                "comparisons cannot be chained: write 'a < b && b < c' instead of 'a < b < c'", ())
    if tok.type == "COMMA" and len(values) > 1 and ctx.is_tok(values[-2], ("EXTENDS", "MODIFIES")):
        return (E_UNEXPECTED_TOKEN,
                f"a role {values[-2].value} only one role: expected '{{' after '{prev.value}'", ())
    if ctx.is_tok(prev, ("ASSIGN",)):
        return E_UNEXPECTED_TOKEN, f"expected the constant's value after ':=', found {found}", ()
    if k < 0 and "ROLE" in expected and "RBRACE" not in expected:
        return (E_OUTSIDE_ROLE,
                f"unexpected {found} outside of a role: expected 'role', 'abstract role' or 'deployment'", ())
    return E_UNEXPECTED_TOKEN, f"unexpected {found}: expected {ctx.describe_expected(expected)}", ()


def unclosed_block(values: list, depth: int, first: Tok, tok: Tok, line: Line) -> Message | None:
    """The block open at ``values[:depth]`` should have been closed before ``first``."""
    k = ctx.open_bracket(values[:depth])
    if k < 0:
        return None
    brace = values[k]
    message = (f"expected '}}' to close {ctx.brace_owner(values, k)} opened on line {line(brace.start)}: "
               f"{ctx.describe_token(first)} starts a member of the role, which cannot be written "
               "inside a method")
    return E_MISSING_CLOSE, message, (*_opened_here(brace),
                                      Related(Span(tok.start, tok.end), "the parser noticed here"))


def stray_else(values: list, prev: Tok | None, line: Line) -> Message:
    """An 'else' with no 'if'; ``prev`` is the token before it."""
    if prev is not None and prev.type == "RBRACE":
        what = ctx.closed_by_last(values)
        message = (f"'else' without a matching 'if': the '}}' on line {line(prev.start)} already closed "
                   f"{what}; is there one '}}' too many?")
        return E_ELSE_WITHOUT_IF, message, (Related(Span(prev.start, prev.end), f"this '}}' closes {what}"),)
    return E_ELSE_WITHOUT_IF, "'else' without a matching 'if'", ()


def end_of_file(values: list, expected: Callable[[], set[str]], line: Line) -> Message:
    k = ctx.open_bracket(values)
    if k >= 0 and values[k].type == "LBRACE":
        brace = values[k]
        message = (f"unexpected end of file: the '{{' of {ctx.brace_owner(values, k)} on line "
                   f"{line(brace.start)} is never closed; add '}}'")
        return E_UNEXPECTED_EOF, message, _opened_here(brace)
    return E_UNEXPECTED_EOF, f"unexpected end of file: expected {ctx.describe_expected(expected())}", ()


def after_deployment(tok: Tok) -> Message:
    return (E_AFTER_DEPLOYMENT, f"unexpected {ctx.describe_token(tok)} after the deployment: "
            "the deployment must come last, after all roles", ())
