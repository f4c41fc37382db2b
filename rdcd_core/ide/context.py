"""What surrounds the cursor, read from the text alone: completion and signature help must work
on incomplete text (``self.`` with nothing after), where the parser has little to offer."""

from __future__ import annotations

import re
from dataclasses import dataclass

COMMENT = re.compile(r"//[^\r\n]*|/\*.*?(\*/|\Z)", re.DOTALL)  # a line comment ends at \r too
ROLE_HEADER = re.compile(r"\brole\s+([A-Za-z_][A-Za-z0-9_]*)(\s+(extends|modifies)\s+([A-Za-z_]\w*))?")
WORD_BEFORE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def blank_comments(text: str) -> str:
    """The text with every comment replaced by spaces (offsets unchanged)."""
    return COMMENT.sub(lambda m: re.sub(r"[^\r\n]", " ", m.group(0)), text)


@dataclass(frozen=True)
class CallContext:
    callee: str
    form: str  # "self", "function" or "global"
    arg_index: int
    open_paren: int  # offset of the '('
    qualifier: str | None = None  # the role of a global call


@dataclass(frozen=True)
class CursorContext:
    prefix: str  # the identifier part before the cursor
    start: int  # where that identifier starts
    before: str  # comment-free text before the identifier
    role: str | None  # the enclosing role (by its header)
    role_modifies: str | None
    after_dot: str | None  # "self" or a name, when the identifier follows `X.`
    call: CallContext | None


def role_tail(before: str) -> str:
    """The text from the last role header on ("" when there is none). Searched backwards, and
    not fooled by names that contain "role" (``connected_role`` in a method body)."""
    position = before.rfind("role")
    while position >= 0:
        boundary = position == 0 or not (before[position - 1].isalnum() or before[position - 1] == "_")
        if boundary and ROLE_HEADER.match(before, position):
            return before[position:]
        position = before.rfind("role", 0, position)
    return ""


def enclosing_role(before: str) -> tuple[str | None, str | None]:
    """The last role header before the cursor, with the role it modifies (if a mixin)."""
    last = ROLE_HEADER.match(role_tail(before))
    if last is None:
        return None, None
    return last.group(1), last.group(4) if last.group(3) == "modifies" else None


def call_context(before: str) -> CallContext | None:
    """The innermost unclosed call around the end of ``before`` and the argument index."""
    depth = 0
    commas = 0
    index = len(before) - 1
    while index >= 0:
        char = before[index]
        if char in ")]}":
            depth += 1
        elif char == "{":
            if depth == 0:
                return None
            depth -= 1
        elif char == "(":
            if depth == 0:
                return _callee(before, index, commas)
            depth -= 1
        elif char == ";" and depth == 0:
            return None
        elif char == "," and depth == 0:
            commas += 1
        index -= 1
    return None


def _callee(before: str, paren: int, commas: int) -> CallContext | None:
    head = before[:paren].rstrip()
    match = WORD_BEFORE.search(head)
    if match is None:
        return None
    name = match.group(0)
    rest = head[: match.start()].rstrip()
    if rest.endswith("."):
        qualifier_match = WORD_BEFORE.search(rest[:-1].rstrip())
        qualifier = qualifier_match.group(0) if qualifier_match else None
        if qualifier == "self":
            return CallContext(name, "self", commas, paren)
        return CallContext(name, "global", commas, paren, qualifier)
    if name == "if":
        return None
    return CallContext(name, "function", commas, paren)


def cursor_context(text: str, offset: int) -> CursorContext:
    offset = max(0, min(offset, len(text)))
    before_all = blank_comments(text[:offset])
    match = WORD_BEFORE.search(before_all)
    prefix = match.group(0) if match else ""
    start = offset - len(prefix)
    before = before_all[: len(before_all) - len(prefix)]
    role, modifies = enclosing_role(before)
    after_dot = None
    stripped = before.rstrip()
    if stripped.endswith("."):
        qualifier = WORD_BEFORE.search(stripped[:-1].rstrip())
        after_dot = qualifier.group(0) if qualifier else None
    return CursorContext(prefix, start, before, role, modifies, after_dot, call_context(before))


def previous_word(before: str) -> str | None:
    match = WORD_BEFORE.search(before.rstrip())
    return match.group(0) if match else None


def in_deployment(before: str) -> bool:
    """Inside the braces of `deployment { … }`."""
    position = before.rfind("deployment")
    if position < 0:
        return False
    tail = before[position + len("deployment"):]
    return tail.lstrip().startswith("{") and "}" not in tail


def assume_role_blocks(before: str) -> list[str]:
    """Mixins whose `assumeRole` block the cursor is inside (outermost first)."""
    found = []
    for match in re.finditer(r"self\s*\.\s*assumeRole\s*\(\s*([A-Za-z_]\w*)\s*,\s*\{", before):
        depth = 0
        for char in before[match.end():]:
            if char == "{":
                depth += 1
            elif char == "}":
                depth -= 1
                if depth < 0:
                    break
        if depth >= 0:
            found.append(match.group(1))
    return found


METHOD_HEADER = re.compile(r"\b([A-Za-z_]\w*)\s*\(([^()]*)\)\s*\{")
NOT_METHODS = frozenset({"if", "else", "role", "deployment"})
VALUES_BEFORE = re.compile(r"\b(neighbours|children)\s*(\([^()]*\))?\s*\.\s*\Z")


def enclosing_parameters(before: str) -> list[str]:
    """The parameters of the method whose body the cursor is in (read from its header)."""
    tail = role_tail(before)
    found: list[str] = []
    for match in METHOD_HEADER.finditer(tail):
        if match.group(1) in NOT_METHODS:
            continue
        depth = 0
        for char in tail[match.end():]:
            if char == "{":
                depth += 1
            elif char == "}":
                depth -= 1
                if depth < 0:
                    break
        if depth >= 0:
            found = [p.strip() for p in match.group(2).split(",")
                     if re.fullmatch(r"[A-Za-z_]\w*", p.strip())]
            if _in_open_block(tail[match.end():], HANDLER):
                found = []  # a handler runs later, without the method's arguments
    return found


HANDLER = re.compile(r"self\s*\.\s*handleEvent\s*\([^{};]*\{")


def _in_open_block(text: str, opener: re.Pattern[str]) -> bool:
    """Some block that ``opener`` starts in ``text`` is still open at its end."""
    for match in opener.finditer(text):
        depth = 0
        for char in text[match.end():]:
            if char == "{":
                depth += 1
            elif char == "}":
                depth -= 1
                if depth < 0:
                    break
        if depth >= 0:
            return True
    return False


def after_values(before: str) -> bool:
    """The cursor follows ``neighbours.``, ``neighbours(…).`` or ``children.``: a module state."""
    return VALUES_BEFORE.search(before[-200:]) is not None
