"""The canonical layout of RDCD programs (the style of ``examples/obstacle_avoidance.rdcd``).

The formatter prints the AST again and threads every comment back in: comments before a role,
member or statement stay on their own lines before it; comments on the same line as the end of
something stay on that line. Formatting never changes the AST (``ast.strip_spans``) and is
idempotent. Blocks passed as arguments stay on one line when the user wrote them on one line.

Lines are the LSP's (``rdcd_core.source``): a text keeps the line break it starts with
(``\\r\\n``, ``\\r`` or ``\\n``), and every line break it prints, those inside block comments
too, is that one. Form feed, U+2028 and the like inside comments are kept as they are: they do
not end a line.
"""

from __future__ import annotations

import difflib

from rdcd_core.diagnostics import TextEdit
from rdcd_core.source import (
    LineIndex,
    Span,
    count_line_breaks,
    has_line_break,
    newline_of,
    normalize_newlines,
    split_lines,
)
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import parse

INDENT = "  "
MAX_INLINE = 100
_SPACE = " \t\f\r\n\ufeff"  # grammar.lark's WS: all a gap between tokens can hold
# Operator characters that would read as one operator if printed side by side ("- -1" is not "--1").
_GLUED = frozenset({"--", "++", "!=", "=="})


def format_text(text: str) -> str | None:
    """The formatted text, or None if the text has syntax errors."""
    program = _parsed(text)
    return format_program(program, text) if program is not None else None


def _parsed(text: str) -> ast.Program | None:
    """The program of ``text``, or None if it has syntax errors."""
    try:
        result = parse(text)
    except Exception:  # the parser promises not to raise; be safe anyway
        return None
    return result.program if result.ok else None


def format_program(program: ast.Program, text: str) -> str:
    return _Printer(program, text).run()


def format_edits(text: str) -> list[TextEdit] | None:
    """Minimal line edits that turn ``text`` into its formatted form (None on syntax errors)."""
    formatted = format_text(text)
    if formatted is None:
        return None
    return line_edits(text, formatted)


def format_range(text: str, span: Span) -> list[TextEdit] | None:
    """Formats the whole lines of the roles (and deployment) that ``span`` touches."""
    program = _parsed(text)
    if program is None:
        return None
    printer = _Printer(program, text)
    printer.run()
    items = [*program.roles, *([program.deployment] if program.deployment else [])]
    index = LineIndex(text)
    touched = [i for i in items if i.span.start <= span.end and span.start <= i.span.end]
    if not touched:
        return []
    first = index.line_col(min(i.span.start for i in touched)).line
    last = index.line_col(max(i.span.end for i in touched)).line
    changed = True
    while changed:  # items sharing a line with the region join it
        changed = False
        for item in items:
            a, b = index.line_col(item.span.start).line, index.line_col(item.span.end).line
            if a <= last and b >= first and (a < first or b > last):
                first, last, changed = min(first, a), max(last, b), True
    start = index.offset(first, 0)
    end = index.line_starts[last + 1] if last + 1 < index.line_count else len(text)
    limit = end + 1 if end == len(text) else end
    lines = [n for n, anchor in enumerate(printer.anchors) if anchor is not None and start <= anchor < limit]
    if not lines:
        return []
    new_text = printer.join(printer.out[lines[0]:lines[-1] + 1])
    if text[start:end] == new_text:
        return []
    return [TextEdit(Span(start, end), new_text)]


def line_edits(old: str, new: str) -> list[TextEdit]:
    """Line-based edits from ``old`` to ``new``."""
    if old == new:
        return []
    old_lines = split_lines(old, keepends=True)
    new_lines = split_lines(new, keepends=True)
    starts = [0]
    for line in old_lines:
        starts.append(starts[-1] + len(line))
    edits: list[TextEdit] = []
    matcher = difflib.SequenceMatcher(None, old_lines, new_lines, autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        edits.append(TextEdit(Span(starts[i1], starts[i2]), "".join(new_lines[j1:j2])))
    return edits


class _Printer:
    def __init__(self, program: ast.Program, text: str) -> None:
        self.program = program
        self.text = text
        self.newline = newline_of(text)
        self.comments = sorted(program.comments, key=lambda c: c.span.start)
        self.next_comment = 0
        self.out: list[str] = []  # finished lines
        self.anchors: list[int | None] = []  # for each line, a source offset it comes from
        self.last_end = 0  # source offset of the end of the last thing printed

    # -- comments ---------------------------------------------------------------------------
    def _pending(self) -> ast.Comment | None:
        if self.next_comment < len(self.comments):
            return self.comments[self.next_comment]
        return None

    def _blank_before(self, offset: int) -> bool:
        gap = self.text[self.last_end:offset]
        return self.last_end > 0 and gap.strip(_SPACE) == "" and count_line_breaks(gap) >= 2

    def _emit(self, line: str, anchor: int) -> None:
        # Trailing blanks go; a form feed or U+2028 closing a comment is the user's text and stays.
        self.out.append(line.rstrip(" \t") if "\n" not in line else line)
        self.anchors.append(anchor)

    @staticmethod
    def _comment(comment: ast.Comment) -> str:
        """A comment's text with its line breaks as ``\\n`` (``join`` writes them in the text's style)."""
        return normalize_newlines(comment.text)

    def join(self, lines: list[str]) -> str:
        """Printed lines as text, every line break the text's own."""
        joined = "\n".join(lines) + "\n"
        return joined if self.newline == "\n" else joined.replace("\n", self.newline)

    def _blank(self) -> None:
        if self.out and self.out[-1] != "":
            self.out.append("")
            self.anchors.append(None)

    def leading(self, offset: int, depth: int) -> None:
        """Own-line comments that start before ``offset``."""
        while (comment := self._pending()) is not None and comment.span.start < offset:
            if self._blank_before(comment.span.start):
                self._blank()
            self._emit(INDENT * depth + self._comment(comment), comment.span.start)
            self.next_comment += 1
            self.last_end = comment.span.end

    def line(self, content: str, end: int, depth: int) -> None:
        """Prints one line whose source ends at ``end``, with the comments inside or after it."""
        trailing: list[str] = []
        anchor = end
        while (comment := self._pending()) is not None:
            inside = comment.span.start < end
            gap = self.text[max(end, self.last_end):comment.span.start]
            after = comment.span.start >= end and not has_line_break(gap)
            if not (inside or after):
                break
            trailing.append(self._comment(comment))
            self.next_comment += 1
            end = max(end, comment.span.end)
            if comment.text.startswith("//"):
                break
        self.last_end = max(self.last_end, end)
        text = INDENT * depth + content
        if trailing:
            text += " " + " ".join(trailing)
        self._emit(text, anchor)
        # comments after a line comment stay pending: the next line or leading() places them

    def separate(self, offset: int) -> None:
        """Keeps one blank line where the user had at least one."""
        if self._blank_before(offset):
            self._blank()

    # -- program ----------------------------------------------------------------------------
    def run(self) -> str:
        items: list[ast.RoleDecl | ast.StateDecl | ast.Deployment] = sorted(
            [*self.program.roles, *self.program.states, *self.program.sequences],
            key=lambda item: item.span.start)
        if self.program.deployment is not None:
            items.append(self.program.deployment)
        for position, item in enumerate(items):
            previous = items[position - 1] if position > 0 else None
            if position > 0 and not (isinstance(item, ast.StateDecl) and isinstance(previous, ast.StateDecl)):
                self._blank()
            self.leading(item.span.start, 0)
            self.separate(item.span.start)
            if isinstance(item, ast.RoleDecl):
                self.role(item)
            elif isinstance(item, ast.Sequence):
                self.sequence(item)
            elif isinstance(item, ast.StateDecl):
                travelling = "travelling " if item.travelling else ""
                self.line(f"{travelling}state {item.name.text} := {expr(item.value)};", item.span.end, 0)
            else:
                self.deployment(item)
        self.leading(len(self.text) + 1, 0)
        while self.out and self.out[-1] == "":
            self.out.pop()
            self.anchors.pop()
        return self.join(self.out) if self.out else ""

    def role(self, role: ast.RoleDecl) -> None:
        header = "abstract role " if role.is_abstract else "role "
        header += role.name.text
        if role.extends is not None:
            header += " extends " + role.extends.text
        if role.modifies is not None:
            header += " modifies " + role.modifies.text
        if not role.members and not self._comments_in(role.span):
            self.line(header + " { }", role.span.end, 0)
            return
        self.line(header + " {", role.header_span.end, 0)
        for member in role.members:
            self.leading(member.span.start, 1)
            self.separate(member.span.start)
            self.member(member)
        self.leading(role.span.end - 1, 1)
        self.line("}", role.span.end, 0)

    def sequence(self, sequence: ast.Sequence) -> None:
        header = "sequence " + sequence.name.text
        if sequence.config is not None:
            header += f"({sequence.config.text})"
        if sequence.modifier is not None:
            header += " " + sequence.modifier.text
        if not sequence.items and not self._comments_in(sequence.span):
            self.line(header + " { }", sequence.span.end, 0)
            return
        self.line(header + " {", sequence.header_span.end, 0)
        for item in sequence.items:
            self.leading(item.span.start, 1)
            self.separate(item.span.start)
            if isinstance(item, ast.SeqStep):
                self.line(seq_step(item), item.span.end, 1)
                continue
            if not item.steps and not self._comments_in(item.span):
                self.line("parallel { }", item.span.end, 1)
                continue
            self.line("parallel {", self.text.index("{", item.span.start) + 1, 1)
            for step in item.steps:
                self.leading(step.span.start, 2)
                self.separate(step.span.start)
                self.line(seq_step(step), step.span.end, 2)
            self.leading(item.span.end - 1, 2)
            self.line("}", item.span.end, 1)
        self.leading(sequence.span.end - 1, 1)
        self.line("}", sequence.span.end, 0)

    def _comments_in(self, span: Span) -> bool:
        comment = self._pending()
        return comment is not None and comment.span.start < span.end

    def deployment(self, deployment: ast.Deployment) -> None:
        names = ", ".join(name.text for name in deployment.roles)
        self.line(f"deployment {{ {names} }}" if names else "deployment { }", deployment.span.end, 0)

    def member(self, member: ast.Member) -> None:
        if isinstance(member, ast.AbstractConstants):
            names = ", ".join(name.text for name in member.names)
            self.line(f"abstract constant {names};", member.span.end, 1)
        elif isinstance(member, ast.ConstantDef):
            self.line(f"constant {member.name.text} := {expr(member.value)};", member.span.end, 1)
        elif isinstance(member, ast.StateDecl):
            travelling = "travelling " if member.travelling else ""
            self.line(f"{travelling}state {member.name.text} := {expr(member.value)};", member.span.end, 1)
        elif isinstance(member, ast.AssignStmt):
            self.line(inline_statement(member), member.span.end, 1)
        elif isinstance(member, ast.Invariant):
            self.line(expr(member.expr) + ";", member.span.end, 1)
        else:
            self.method(member)

    def method(self, method: ast.MethodDecl) -> None:
        params = ", ".join(param.text for param in method.params)
        words = [m.keyword for m in method.modifiers] + [f"{method.name.text}({params})"]
        head = " ".join(words)
        if method.body is None:
            self.line(head + ";", method.span.end, 1)
            return
        self.block(method.body, head + " ", 1, "")

    # -- statements ---------------------------------------------------------------------------
    def block(self, block: ast.Block, prefix: str, depth: int, suffix: str) -> None:
        """``prefix{`` … ``}suffix``, the statements one level deeper."""
        if not block.statements and not self._comments_in(block.span):
            self.line(prefix + "{ }" + suffix, block.span.end, depth)
            return
        self.line(prefix + "{", block.span.start + 1, depth)
        for statement in block.statements:
            self.leading(statement.span.start, depth + 1)
            self.separate(statement.span.start)
            self.statement(statement, depth + 1)
        self.leading(block.span.end - 1, depth + 1)
        self.line("}" + suffix, block.span.end, depth)

    def statement(self, statement: ast.Stmt, depth: int, prefix: str = "") -> None:
        if isinstance(statement, ast.Block):
            self.block(statement, prefix, depth, "")
        elif isinstance(statement, ast.EmptyStmt):
            self.line(prefix + ";", statement.span.end, depth)
        elif isinstance(statement, ast.CallStmt):
            self.call_statement(statement, depth, prefix)
        elif isinstance(statement, ast.AssignStmt):
            self.line(prefix + inline_statement(statement), statement.span.end, depth)
        else:
            self.if_statement(statement, depth, prefix)

    def if_statement(self, statement: ast.IfStmt, depth: int, prefix: str) -> None:
        head = f"{prefix}if ({expr(statement.condition)})"
        self.body(statement.then_body, head, statement.condition.span.end + 1, depth)
        if statement.else_body is None:
            return
        else_start = statement.else_span.start if statement.else_span else statement.else_body.span.start
        self.leading(else_start, depth)
        else_end = statement.else_span.end if statement.else_span else else_start
        if isinstance(statement.else_body, ast.IfStmt):
            self.if_statement(statement.else_body, depth, "else ")
        else:
            self.body(statement.else_body, "else", else_end, depth)

    def body(self, body: ast.Stmt, head: str, head_end: int, depth: int) -> None:
        if isinstance(body, ast.Block):
            self.block(body, head + " ", depth, "")
        else:
            self.line(head, head_end, depth)
            self.leading(body.span.start, depth + 1)
            self.statement(body, depth + 1)

    def call_statement(self, statement: ast.CallStmt, depth: int, prefix: str) -> None:
        call = statement.call
        args = call.args
        multi = [a for a in args if isinstance(a, ast.Block) and not self._inline_block(a, depth)]
        if not multi:
            self.line(prefix + expr(call) + ";", statement.span.end, depth)
            return
        # a call whose last block argument spans several lines: `self.f(a, {` … `});`
        block = multi[-1]
        before = [expr(a) for a in args[: args.index(block)]]
        head = prefix + call_head(call) + "(" + "".join(b + ", " for b in before)
        after = args[args.index(block) + 1:]
        tail = "".join(", " + expr(a) for a in after) + ");"
        self.block(block, head, depth, tail)
        self.last_end = max(self.last_end, statement.span.end)

    def _inline_block(self, block: ast.Block, depth: int) -> bool:
        source = self.text[block.span.start:block.span.end]
        if has_line_break(source) or self._comments_in_range(block.span):
            return False
        return len(INDENT * depth) + len(inline_block(block)) <= MAX_INLINE

    def _comments_in_range(self, span: Span) -> bool:
        return any(span.start <= c.span.start < span.end for c in self.comments)


# -- expressions (pure functions) -----------------------------------------------------------------
def expr(node: ast.Arg) -> str:
    if isinstance(node, ast.IntLit):
        return str(node.value)
    if isinstance(node, ast.NameRef):
        return node.name.text
    if isinstance(node, ast.Unary):
        operand = expr(node.operand)
        return node.op + (" " if node.op[-1] + operand[:1] in _GLUED else "") + operand
    if isinstance(node, ast.Binary):
        return f"{expr(node.left)} {node.op} {expr(node.right)}"
    if isinstance(node, ast.Paren):
        return f"({expr(node.expr)})"
    if isinstance(node, ast.Block):
        return inline_block(node)
    if isinstance(node, ast.NeighbourValues):
        source = "children" if node.children else "neighbours"
        where = f"({expr(node.where)})" if node.where is not None else ""
        return f"{source}{where}.{node.name.text}"
    if isinstance(node, ast.SelfCall):
        if not node.has_parens:
            return "self." + node.name.text
    return call_head(node) + "(" + ", ".join(expr(a) for a in node.args) + ")"


def seq_step(step: ast.SeqStep) -> str:
    condition = f"({expr(step.condition)})" if step.condition is not None else ""
    args = ", ".join(expr(a) for a in step.args)
    return f"{step.role.text}{condition}.{step.action.text}({args});"


def call_head(call: ast.Call) -> str:
    if isinstance(call, ast.SelfCall):
        return "self." + call.name.text
    if isinstance(call, ast.GlobalCall):
        return f"{call.role.text}.{call.name.text}"
    return call.name.text


def inline_block(block: ast.Block) -> str:
    if not block.statements:
        return "{ }"
    return "{ " + " ".join(inline_statement(s) for s in block.statements) + " }"


def inline_statement(statement: ast.Stmt) -> str:
    if isinstance(statement, ast.Block):
        return inline_block(statement)
    if isinstance(statement, ast.EmptyStmt):
        return ";"
    if isinstance(statement, ast.CallStmt):
        return expr(statement.call) + ";"
    if isinstance(statement, ast.AssignStmt):
        return f"{statement.name.text} := {expr(statement.value)};"
    text = f"if ({expr(statement.condition)}) {inline_statement(statement.then_body)}"
    if statement.else_body is not None:
        text += " else " + inline_statement(statement.else_body)
    return text
