"""What the parser was in the middle of when it met an error, read off its value stack.

The value stack holds shifted tokens (``Tok``) and reduced AST nodes; an opening bracket still
on the stack is one that is not closed yet, so the innermost one tells where the error is.
"""

from __future__ import annotations

from lark import Tree

from rdcd_core.syntax import ast
from rdcd_core.syntax.lexer import Tok

TOKEN_TEXT = {
    "LBRACE": "'{'", "RBRACE": "'}'", "LPAR": "'('", "RPAR": "')'", "COMMA": "','", "SEMI": "';'",
    "DOT": "'.'", "ASSIGN": "':='", "OR": "'||'", "AND": "'&&'", "EQ": "'=='", "NE": "'!='",
    "LE": "'<='", "GE": "'>='", "LT": "'<'", "GT": "'>'", "PLUS": "'+'", "MINUS": "'-'",
    "STAR": "'*'", "SLASH": "'/'", "PERCENT": "'%'",
    "BANG": "'!'", "NAME": "a name", "INT": "a number", "$END": "the end of the file",
}
EXPRESSION_START = frozenset({"NAME", "INT", "SELF", "LPAR", "MINUS", "BANG", "NEIGHBOURS", "CHILDREN"})
OPERATORS = frozenset({"OR", "AND", "EQ", "NE", "LE", "GE", "LT", "GT", "PLUS", "MINUS", "STAR", "SLASH",
                       "PERCENT"})
MEMBER_START = frozenset({"ABSTRACT", "CONSTANT", "STARTUP", "BEHAVIOR", "COMMAND", "STATE", "TRAVELLING"})
_COMPARISONS = frozenset({"<", ">", "<=", ">="})


def describe_token(tok: Tok) -> str:
    if tok.type == "NAME":
        return f"name '{tok.value}'" if len(tok.value) <= 40 else f"name '{tok.value[:40]}...'"
    if tok.type == "INT":
        return f"number {tok.value[:20]}"
    if tok.type == "$END":
        return "end of file"
    if tok.value.isalpha():
        return f"keyword '{tok.value}'"
    return TOKEN_TEXT.get(tok.type, repr(tok.value))


def describe_expected(expected: set[str]) -> str:
    """A short English list of what the parser could accept."""
    items: list[str] = []
    rest = set(expected)
    if EXPRESSION_START <= rest or {"NAME", "INT", "SELF"} <= rest:
        items.append("an expression")
        rest -= EXPRESSION_START
    if len(rest & OPERATORS) > 3:
        items.append("an operator")
        rest -= OPERATORS
    if MEMBER_START <= rest:
        items.insert(0, "a member")
        rest -= MEMBER_START
    order = ["SEMI", "RPAR", "RBRACE", "COMMA", "LBRACE", "LPAR", "ASSIGN", "DOT", "NAME", "INT"]
    for name in sorted(rest, key=lambda t: (order.index(t) if t in order else 99, t)):
        if name in TOKEN_TEXT:
            items.append(TOKEN_TEXT[name])
        else:
            items.append(f"'{name.lower()}'")
    if not items:
        return "nothing more"
    if len(items) > 6:
        items = items[:6] + ["…"]
    if len(items) == 1:
        return items[0]
    return ", ".join(items[:-1]) + " or " + items[-1]


def open_bracket(values: list) -> int:
    """Index in ``values`` of the innermost unclosed '{' or '(' (-1 if none).

    A closing bracket may still be on the stack (shifted, not yet reduced): it cancels its partner.
    """
    closed = 0
    for k in range(len(values) - 1, -1, -1):
        value = values[k]
        if isinstance(value, Tok):
            ttype = value.type
            if ttype == "RBRACE" or ttype == "RPAR":
                closed += 1
            elif ttype == "LBRACE" or ttype == "LPAR":
                if closed == 0:
                    return k
                closed -= 1
    return -1


def _tok(values: list, k: int, ttype: str) -> Tok | None:
    if 0 <= k < len(values):
        value = values[k]
        if isinstance(value, Tok) and value.type == ttype:
            return value
    return None


def brace_owner(values: list, k: int) -> str:
    """What the '{' at ``values[k]`` opens, e.g. "role 'Axle'" or "method 'steer'"."""
    for back in range(1, 5):
        if _tok(values, k - back, "ROLE") and _tok(values, k - back + 1, "NAME"):
            return f"role '{values[k - back + 1].value}'"
    if _tok(values, k - 1, "DEPLOYMENT"):
        return "the deployment"
    if _tok(values, k - 1, "RPAR") and _tok(values, k - 2, "LPAR") and _tok(values, k - 3, "NAME"):
        return f"method '{values[k - 3].value}'"
    if _tok(values, k - 1, "ELSE"):
        return "the 'else' block"
    if _tok(values, k - 1, "RPAR"):
        return "the 'if' block"
    if _tok(values, k - 1, "COMMA") or _tok(values, k - 1, "LPAR"):
        return "the block argument"
    return "the block"


def paren_owner(values: list, k: int) -> str:
    if _tok(values, k - 1, "IF"):
        return "the 'if' condition"
    name = _tok(values, k - 1, "NAME")
    if name is not None:
        return f"the arguments of '{name.value}'"
    return "the parenthesis"


def in_role_body(values: list, k: int) -> bool:
    return k >= 0 and brace_owner(values, k).startswith("role ")


def current_item(values: list, k: int) -> list:
    """The values of the member or statement being parsed in the bracket at ``k``."""
    start = k + 1
    for index in range(len(values) - 1, k, -1):
        value = values[index]
        if isinstance(value, _COMPLETE) or (
                isinstance(value, Tree) and value.children and isinstance(value.children[-1], _COMPLETE)):
            start = index + 1
            break
    return values[start:]


_COMPLETE = (ast.Invariant, ast.ConstantDef, ast.AbstractConstants, ast.MethodDecl, ast.RoleDecl,
             ast.CallStmt, ast.EmptyStmt, ast.IfStmt, ast.Block)


def construct_name(values: list, k: int) -> str:
    """Names the member or statement under construction, for "expected ';' after …"."""
    item = current_item(values, k)
    if not item:
        return "the previous item"
    first = item[0]
    if isinstance(first, Tree) and first.children:
        first = first.children[0]
    if isinstance(first, Tok):
        if first.type == "CONSTANT":
            return "the constant definition"
        if first.type == "ABSTRACT" and len(item) > 1 and _tok(item, 1, "CONSTANT"):
            return "the abstract constant list"
    if isinstance(first, ast.Modifier) or (isinstance(first, Tok) and first.type in MEMBER_START):
        return "the method declaration"
    if in_role_body(values, k):
        return "the invariant"
    return "the call"


def is_tok(value: object, types: tuple[str, ...]) -> bool:
    return isinstance(value, Tok) and value.type in types


def start_of(value: object) -> int | None:
    """Where a value of the stack starts in the text (None for a placeholder)."""
    while isinstance(value, Tree):
        value = value.children[0] if value.children else None
    if isinstance(value, Tok):
        return value.start
    span = getattr(value, "span", None)
    return span.start if span is not None else None


def role_header(values: list) -> str | None:
    """The role's name if the parser is in a role header (``role NAME [extends NAME]``)."""
    for back in range(2, 6):
        if len(values) >= back and is_tok(values[-back], ("ROLE",)):
            name = values[-back + 1]
            return name.value if is_tok(name, ("NAME",)) else None
    return None


def concrete_method_header(values: list) -> bool:
    """Whether the parser just read ``modifiers name ( )`` of a method that is not abstract."""
    if len(values) < 4 or not (is_tok(values[-1], ("RPAR",)) and is_tok(values[-2], ("LPAR",))
                               and is_tok(values[-3], ("NAME",))):
        return False
    modifiers = values[-4].children if isinstance(values[-4], Tree) else [values[-4]]
    if not all(isinstance(m, ast.Modifier) for m in modifiers):
        return False
    return not any(m.keyword == "abstract" for m in modifiers)


def after_comparison(values: list) -> bool:
    """Whether the expression just read is a comparison (so another one would chain)."""
    if values and isinstance(values[-1], ast.Binary) and values[-1].op in _COMPARISONS:
        return True
    return len(values) > 1 and isinstance(values[-2], Tok) and values[-2].value in _COMPARISONS



def closed_by_last(values: list) -> str:
    """What the '}' just read closed, e.g. "method 'steer'"."""
    top = values[-1] if values else None
    if isinstance(top, Tok) and top.type == "RBRACE":  # not reduced yet: find its '{'
        k = open_bracket(values[:-1])
        if k >= 0 and values[k].type == "LBRACE":
            return brace_owner(values, k)
    if isinstance(top, ast.Block):
        return brace_owner(values, len(values) - 1)
    if isinstance(top, Tree) and top.children:
        top = top.children[-1]
    if isinstance(top, ast.MethodDecl):
        return f"method '{top.name.text}'"
    if isinstance(top, ast.RoleDecl):
        return f"role '{top.name.text}'"
    return "the block before it"


def name_kind(values: list) -> str:
    """What kind of name the parser expects after the last token ("a role", "a constant", …)."""
    prev = values[-1] if values else None
    if isinstance(prev, Tok):
        if prev.type in ("ROLE", "EXTENDS", "MODIFIES"):
            return "a role"
        if prev.type == "CONSTANT":
            return "a constant"
        if prev.type == "DOT":
            return "a method"
        if prev.type == "COMMA":
            k = open_bracket(values)
            return "a role" if k >= 0 and brace_owner(values, k) == "the deployment" else "a constant"
    return "a"
