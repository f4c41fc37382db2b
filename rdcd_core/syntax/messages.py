"""The texts of the syntax diagnostics: what went wrong, where, and what the parser expected.

Each function returns a ``Message``; ``line`` turns an offset into a 1-based line. A message whose
``after_previous`` is set says that something is missing rather than that a token is wrong: the
diagnostic then points just after the previous token (where the missing text belongs, usually the end
of a line), not at the next token, which may be lines further down (as rustc and tsc do).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

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


class Message(NamedTuple):
    code: str
    text: str
    related: tuple[Related, ...] = ()
    after_previous: bool = False  # point just after the previous token (something is missing there)


# the text of a punctuation token (the ones the recovery makes up among them)
TEXT = {name: shown[1:-1] for name, shown in ctx.TOKEN_TEXT.items() if shown.startswith("'")}


def _opened_here(tok: Tok) -> tuple[Related, ...]:
    return (Related(Span(tok.start, tok.end), "opened here"),)


def inserted(values: list, tok: Tok, tokens: tuple[str, ...], line: Line, prev: Tok | None) -> Message:
    """The parser mended the text by inserting ``tokens`` right after ``prev``, before ``tok``."""
    first = tokens[0]
    found = f"found {ctx.describe_token(tok)}"
    k = ctx.open_bracket(values)
    opener = values[k].type if k >= 0 else ""
    if first == "SEMI":
        return Message(E_MISSING_SEMICOLON, f"expected ';' after {ctx.construct_name(values, k)}, {found}",
                       (), True)
    if first == "RPAR" and opener == "LPAR":
        paren = values[k]
        return Message(E_MISSING_CLOSE, f"expected ')' to close {ctx.paren_owner(values, k)} opened on line "
                       f"{line(paren.start)}, {found}", _opened_here(paren), True)
    if first == "RBRACE" and opener == "LBRACE":
        brace = values[k]
        return Message(E_MISSING_CLOSE, f"expected '}}' to close {ctx.brace_owner(values, k)} opened on line "
                       f"{line(brace.start)}, {found}", _opened_here(brace), True)
    return Message(E_UNEXPECTED_TOKEN, f"{_expected_insertion(values, k, tokens, prev)}, {found}", (), True)


def _expected_insertion(values: list, k: int, tokens: tuple[str, ...], prev: Tok | None) -> str:
    """"expected …" for an insertion other than ';' or a closing bracket."""
    first = tokens[0]
    role = ctx.role_header(values)
    if first == "LBRACE" and ctx.is_tok(values[-1] if values else None, ("RPAR",)):
        return "expected a body '{ … }' or ';' after the method header"
    if first == "LBRACE" and role is not None:
        return f"expected '{{' to open the body of role '{role}'"
    if first == "COMMA" and k >= 0:
        owner = ctx.brace_owner(values, k) if values[k].type == "LBRACE" else ctx.paren_owner(values, k)
        if owner == "the deployment":
            return "expected ',' between the role names"
        if owner.startswith("the arguments"):
            return f"expected ',' between {owner}"
    if first == "COMMA" and ctx.construct_name(values, k) == "the abstract constant list":
        return "expected ',' between the constant names"
    if first == "ASSIGN" and prev is not None:
        return f"expected ':=' after the constant's name '{prev.value}'"
    what = "".join(TEXT[c] for c in tokens)  # e.g. '()' after the name of a method
    return f"expected '{what}'" + (f" after {ctx.describe_token(prev)}" if prev is not None else "")


def unexpected(values: list, tok: Tok, expected: set[str], dangling: Tok | None = None) -> Message:
    """``tok`` cannot follow what the parser read; ``expected`` is what could.

    ``dangling`` is the previous token when it ends an earlier line in the middle of a construct (not
    after ';', '{' or '}'): then what is expected is missing at the end of that line, and the message
    says so there instead of blaming ``tok``.
    """
    found = ctx.describe_token(tok)
    k = ctx.open_bracket(values)
    prev = values[-1] if values else None
    opener = values[k].type if k >= 0 else ""
    missing = dangling is not None
    if tok.type in ("RBRACE", "RPAR") and opener != ("LBRACE" if tok.type == "RBRACE" else "LPAR"):
        want = "{" if tok.type == "RBRACE" else "("
        message = f"unmatched '{tok.value}': there is no open '{want}' to close"
        if opener:
            message += f" here (the innermost open bracket is a '{values[k].value}')"
        return Message(E_UNMATCHED_CLOSE, message)
    if expected and expected <= {"NAME"}:
        after = f" after '{prev.value}'" if isinstance(prev, Tok) and prev.value else ""
        return Message(E_EXPECTED_NAME, f"expected {ctx.name_kind(values)} name{after}, found {found}", (),
                       missing)
    if tok.value in ("<", ">", "<=", ">=") and ctx.after_comparison(values):
        return Message(E_CHAINED_COMPARISON,
                       "comparisons cannot be chained: write 'a < b && b < c' instead of 'a < b < c'")
    if tok.type == "COMMA" and len(values) > 1 and ctx.is_tok(values[-2], ("EXTENDS", "MODIFIES")):
        return Message(E_UNEXPECTED_TOKEN,
                       f"a role {values[-2].value} only one role: expected '{{' after '{prev.value}'")
    if ctx.is_tok(prev, ("ASSIGN",)):
        what = {"CONSTANT": "the constant's value", "STATE": "the state's initial value"}.get(
            values[-3].type if len(values) >= 3 and isinstance(values[-3], Tok) else "", "the new value")
        return Message(E_UNEXPECTED_TOKEN, f"expected {what} after ':=', found {found}", (),
                       missing)
    if k < 0 and "ROLE" in expected and "RBRACE" not in expected:
        return Message(E_OUTSIDE_ROLE, f"unexpected {found} outside of a role: "
                       "expected 'role', 'abstract role' or 'deployment'")
    if dangling is not None:
        return Message(E_UNEXPECTED_TOKEN, f"expected {ctx.describe_expected(expected)} after "
                       f"{ctx.describe_token(dangling)}, found {found}", (), True)
    return Message(E_UNEXPECTED_TOKEN, f"unexpected {found}: expected {ctx.describe_expected(expected)}")


def unclosed_block(values: list, depth: int, first: Tok, tok: Tok, line: Line) -> Message | None:
    """The block open at ``values[:depth]`` should have been closed before ``first`` (the '}' is missing
    after the token before it)."""
    k = ctx.open_bracket(values[:depth])
    if k < 0:
        return None
    brace = values[k]
    message = (f"expected '}}' to close {ctx.brace_owner(values, k)} opened on line {line(brace.start)}: "
               f"{ctx.describe_token(first)} on line {line(first.start)} starts a member of the role, "
               "which cannot be written inside a method")
    return Message(E_MISSING_CLOSE, message, (*_opened_here(brace),
                                              Related(Span(first.start, first.end), "this starts a member"),
                                              Related(Span(tok.start, tok.end), "the parser noticed here")),
                   True)


def stray_else(values: list, prev: Tok | None, line: Line) -> Message:
    """An 'else' with no 'if'; ``prev`` is the token before it."""
    if prev is not None and prev.type == "RBRACE":
        what = ctx.closed_by_last(values)
        message = (f"'else' without a matching 'if': the '}}' on line {line(prev.start)} already closed "
                   f"{what}; is there one '}}' too many?")
        return Message(E_ELSE_WITHOUT_IF, message,
                       (Related(Span(prev.start, prev.end), f"this '}}' closes {what}"),))
    return Message(E_ELSE_WITHOUT_IF, "'else' without a matching 'if'")


def end_of_file(values: list, expected: Callable[[], set[str]], line: Line) -> Message:
    k = ctx.open_bracket(values)
    if k >= 0 and values[k].type == "LBRACE":
        brace = values[k]
        message = (f"unexpected end of file: the '{{' of {ctx.brace_owner(values, k)} on line "
                   f"{line(brace.start)} is never closed; add '}}'")
        return Message(E_UNEXPECTED_EOF, message, _opened_here(brace))
    return Message(E_UNEXPECTED_EOF, f"unexpected end of file: expected {ctx.describe_expected(expected())}")


def after_deployment(tok: Tok) -> Message:
    return Message(E_AFTER_DEPLOYMENT, f"unexpected {ctx.describe_token(tok)} after the deployment: "
                   "the deployment must come last, after all roles")
