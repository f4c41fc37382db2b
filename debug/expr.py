"""A tiny expression language for breakpoint conditions, log points and ``evaluate``.

It reads names (the variables of a module, see ``debug.inspect.names``), integers, strings,
``true``/``false``/``none``, comparisons (== != < <= > >=), ``and``, ``or``, ``not``, unary minus and
parentheses. Nothing else exists: no calls, no attributes, no Python ``eval``; evaluating reads
variables and never runs code.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

MAX_LENGTH = 1000

_TOKEN = re.compile(r"""\s*(?:(?P<num>\d+)|(?P<str>"(?:[^"\\]|\\.)*"|'(?:[^'\\]|\\.)*')|"""
                    r"""(?P<name>[A-Za-z_][A-Za-z0-9_.]*)|(?P<op>==|!=|<=|>=|&&|\|\||[<>()!-]))""")
_WORDS = {"and": "&&", "or": "||", "not": "!"}
_CONSTANTS = {"true": True, "false": False, "none": None, "True": True, "False": False, "None": None}


class ExprError(ValueError):
    pass


@dataclass(frozen=True)
class Expr:
    text: str
    tree: tuple

    def evaluate(self, names: Mapping[str, Any]) -> Any:
        return _eval(self.tree, names)


def parse(text: str) -> Expr:
    if len(text) > MAX_LENGTH:
        raise ExprError(f"an expression of more than {MAX_LENGTH} characters")
    tokens = _tokens(text)
    parser = _Parser(tokens)
    tree = parser.disjunction()
    if parser.i != len(tokens):
        raise ExprError(f"unexpected {tokens[parser.i][1]!r}")
    return Expr(text, tree)


def _tokens(text: str) -> list[tuple[str, Any]]:
    out: list[tuple[str, Any]] = []
    at = 0
    while at < len(text):
        if not text[at:].strip():
            break
        m = _TOKEN.match(text, at)
        if m is None or m.end() == at:
            raise ExprError(f"cannot read {text[at:].strip()[:20]!r}")
        at = m.end()
        if m.group("num"):
            out.append(("value", int(m.group("num"))))
        elif m.group("str"):
            out.append(("value", _unquote(m.group("str"))))
        elif m.group("name"):
            word = m.group("name")
            if word in _WORDS:
                out.append(("op", _WORDS[word]))
            elif word in _CONSTANTS:
                out.append(("value", _CONSTANTS[word]))
            else:
                out.append(("name", word))
        else:
            out.append(("op", m.group("op")))
    if not out:
        raise ExprError("an empty expression")
    return out


def _unquote(quoted: str) -> str:
    return re.sub(r"\\(.)", r"\1", quoted[1:-1])


class _Parser:
    def __init__(self, tokens: list[tuple[str, Any]]) -> None:
        self.tokens, self.i = tokens, 0

    def _peek(self) -> tuple[str, Any] | None:
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def _take_op(self, *ops: str) -> str | None:
        t = self._peek()
        if t is not None and t[0] == "op" and t[1] in ops:
            self.i += 1
            return t[1]
        return None

    def disjunction(self) -> tuple:
        left = self.conjunction()
        while self._take_op("||"):
            left = ("or", left, self.conjunction())
        return left

    def conjunction(self) -> tuple:
        left = self.negation()
        while self._take_op("&&"):
            left = ("and", left, self.negation())
        return left

    def negation(self) -> tuple:
        if self._take_op("!"):
            return ("not", self.negation())
        return self.comparison()

    def comparison(self) -> tuple:
        left = self.unary()
        op = self._take_op("==", "!=", "<", "<=", ">", ">=")
        if op:
            return ("cmp", op, left, self.unary())
        return left

    def unary(self) -> tuple:
        if self._take_op("-"):
            return ("neg", self.unary())
        return self.atom()

    def atom(self) -> tuple:
        t = self._peek()
        if t is None:
            raise ExprError("the expression ends too early")
        if self._take_op("("):
            inner = self.disjunction()
            if not self._take_op(")"):
                raise ExprError("a '(' without its ')'")
            return inner
        if t[0] in ("value", "name"):
            self.i += 1
            return t
        raise ExprError(f"unexpected {t[1]!r}")


_CMP = {"==": lambda a, b: a == b, "!=": lambda a, b: a != b, "<": lambda a, b: a < b,
        "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}


def _eval(tree: tuple, names: Mapping[str, Any]) -> Any:
    kind = tree[0]
    if kind == "value":
        return tree[1]
    if kind == "name":
        if tree[1] not in names:
            raise ExprError(f"unknown name {tree[1]!r} (known: {', '.join(sorted(names))})")
        return names[tree[1]]
    if kind == "not":
        return not _eval(tree[1], names)
    if kind == "and":
        return bool(_eval(tree[1], names)) and bool(_eval(tree[2], names))
    if kind == "or":
        return bool(_eval(tree[1], names)) or bool(_eval(tree[2], names))
    if kind == "neg":
        value = _eval(tree[1], names)
        if not isinstance(value, int) or isinstance(value, bool):
            raise ExprError(f"cannot negate {value!r}")
        return -value
    a, b = _eval(tree[2], names), _eval(tree[3], names)
    try:
        return _CMP[tree[1]](a, b)
    except TypeError:
        raise ExprError(f"cannot compare {a!r} {tree[1]} {b!r}") from None
