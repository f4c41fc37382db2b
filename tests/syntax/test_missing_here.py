"""Something missing is reported where it is missing: just after the previous token (usually the
end of a line), not at the next token, which may be lines further down (as rustc and tsc do)."""

from __future__ import annotations

import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from rdcd_core.formatter import format_text
from rdcd_core.source import LineIndex
from rdcd_core.syntax import parse
from tests.conftest import EXAMPLES
from tests.semantics.test_fuzz_programs import programs


def where(text: str) -> list[tuple[str, str, str]]:
    """(code, "line:column" of start and end, message) of every diagnostic, 1-based."""
    lines = LineIndex(text)

    def at(offset: int) -> str:
        position = lines.line_col(offset)
        return f"{position.line + 1}:{position.column + 1}"

    return [(d.code, f"{at(d.span.start)}-{at(d.span.end)}", d.message) for d in parse(text).diagnostics]


@pytest.mark.parametrize(("text", "code", "span", "message"), [
    # ';' at the end of a line, the next token on the next line
    ("role A {\n  self.x() > 0\n  self.y() > 1;\n}\ndeployment { A }",
     "E004", "2:15-2:15", "expected ';' after the invariant, found keyword 'self'"),
    ("role A {\n  constant c := 3\n}\ndeployment { A }",
     "E004", "2:18-2:18", "expected ';' after the constant definition, found '}'"),
    ("role A {\n  startup f() {\n    self.sleep()\n    self.x();\n  }\n}\ndeployment { A }",
     "E004", "3:17-3:17", "expected ';' after the call"),
    ("role A {\n  startup go() {\n    if (x) self.a()\n    else self.b();\n  }\n}\ndeployment { A }",
     "E004", "3:20-3:20", "found keyword 'else'"),
    # ')' and '}'
    ("role A {\n  startup f() {\n    if (a > 0\n      self.sleep();\n  }\n}\ndeployment { A }",
     "E012", "3:14-3:14", "expected ')' to close the 'if' condition opened on line 3, found keyword 'self'"),
    ("role A {\n  self.x(\n}\ndeployment { A }",
     "E012", "2:10-2:10", "expected ')' to close the arguments of 'x' opened on line 2, found '}'"),
    ("role A {\n  startup f() {\n    self.sleep();\n\n  command g() { }\n}\ndeployment { A }",
     "E012", "3:18-3:18", "expected '}' to close method 'f' opened on line 2, found keyword 'command'"),
    ("role A {\n  startup go() {\n    self.sleep();\n\n  self.x() > 0;\n}\ndeployment { A }",
     "E012", "3:18-3:18", "keyword 'self' on line 5 starts a member of the role"),
    # ',' ':=' '{' '()'
    ("role A { }\nrole B { }\ndeployment { A\n  B }",
     "E003", "3:15-3:15", "expected ',' between the role names, found name 'B'"),
    ("role A {\n  startup f() {\n    self.foo(1 2);\n  }\n}\ndeployment { A }",
     "E003", "3:15-3:15", "expected ',' between the arguments of 'foo', found number 2"),
    ("role A {\n  abstract constant a b;\n}\ndeployment { A }",
     "E003", "2:22-2:22", "expected ',' between the constant names, found name 'b'"),
    ("role A {\n  constant c 3;\n}\ndeployment { A }",
     "E003", "2:13-2:13", "expected ':=' after the constant's name 'c', found number 3"),
    ("role A\n  self.x() > 0;\n}\ndeployment { A }",
     "E003", "1:7-1:7", "expected '{' to open the body of role 'A', found keyword 'self'"),
    ("role A {\n  startup go()\n    self.sleep();\n  }\n}\ndeployment { A }",
     "E003", "2:15-2:15", "expected a body '{ … }' or ';' after the method header, found keyword 'self'"),
    ("role A {\n  startup go {\n  }\n}\ndeployment { A }",
     "E003", "2:13-2:13", "expected '()' after name 'go', found '{'"),
    # a line left unfinished: what is expected is missing at its end
    ("role A {\n  self.x() >\n  startup go() { }\n}\ndeployment { A }",
     "E003", "2:13-2:13", "expected an expression after '>', found keyword 'startup'"),
    ("role A {\n  constant c :=\n  startup go() { }\n}\ndeployment { A }",
     "E003", "2:16-2:16", "expected the constant's value after ':=', found keyword 'startup'"),
    ("role A extends\n{\n}\ndeployment { A }",
     "E007", "1:15-1:15", "expected a role name after 'extends', found '{'"),
])
def test_missing_text_is_reported_where_it_belongs(text: str, code: str, span: str, message: str) -> None:
    found = where(text)
    assert len(found) == 1, found
    assert found[0][:2] == (code, span), found
    assert message in found[0][2], found


@pytest.mark.parametrize(("text", "code", "span"), [
    # the token found is the wrong one: the error stays on it
    ("role A extends 3 {\n}\ndeployment { A }", "E007", "1:16-1:17"),
    ("role A {\n  self.x() > 0;\n  > 1;\n}\ndeployment { A }", "E003", "3:3-3:4"),
    ("role A { self.x() > > 1; }\ndeployment { A }", "E003", "1:21-1:22"),
    ("role A {\n  self.x() > 0;\n  )\n}\ndeployment { A }", "E005", "3:3-3:4"),
    ("role A { }\nself.sleep();\ndeployment { A }", "E009", "2:1-2:5"),
    ("role A {\n  0 < self.x() < 5;\n}\ndeployment { A }", "E011", "2:16-2:17"),
    ("deployment { A }\nrole A { }", "E014", "2:1-2:5"),
    ("role A {\n  self.x() > 0;\n", "E006", "3:1-3:1"),
])
def test_a_wrong_token_is_reported_on_itself(text: str, code: str, span: str) -> None:
    found = where(text)
    assert len(found) == 1, found
    assert found[0][:2] == (code, span), found


def test_figure5_still_reports_the_stray_else_at_line_41() -> None:
    text = (EXAMPLES / "figure5_verbatim.rdcd").read_text(encoding="utf-8")
    code, span, message = where(text)[0]
    assert (code, span.split("-")[0]) == ("E013", "41:5")
    assert "the '}' on line 40 already closed method 'steer'" in message


def _line_ending_semicolons(text: str) -> list[int]:
    """Offsets of the ';' that end a statement or member at the end of a line (not an empty
    statement alone on its line, nor one in a comment)."""
    offsets = []
    start = 0
    for line in text.split("\n"):
        code = line.rstrip()
        if code.endswith(";") and code.strip() != ";" and "//" not in code and "*" not in code:
            offsets.append(start + len(code) - 1)
        start += len(line) + 1
    return offsets


def check_deleted_semicolon(text: str, offset: int) -> None:
    """Deleting the ';' at ``offset`` gives one E004 exactly there, whose fix gives ``text`` back
    (unless the next line goes on with the expression: ``x > 0`` then ``-1 > 0;`` is ``x > 0 - 1 > 0``)."""
    assert text[offset] == ";"
    broken = text[:offset] + text[offset + 1:]
    diagnostics = parse(broken).diagnostics
    if not diagnostics:
        assert text[offset + 1:].lstrip()[0] in "-(", broken
        return
    assert [d.code for d in diagnostics] == ["E004"], (broken, diagnostics)
    (diagnostic,) = diagnostics
    assert diagnostic.span.start == diagnostic.span.end == offset, (broken, diagnostic)
    (fix,) = diagnostic.fixes
    (edit,) = fix.edits
    assert broken[:edit.span.start] + edit.new_text + broken[edit.span.end:] == text


@pytest.mark.parametrize("name", ["obstacle_avoidance.rdcd", "snake_wave.rdcd"])
def test_each_statement_ending_semicolon_deleted_from_an_example(name: str) -> None:
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    assert parse(text).ok
    offsets = _line_ending_semicolons(text)
    assert len(offsets) >= 10
    for offset in offsets:
        check_deleted_semicolon(text, offset)


@given(programs, st.integers(0, 10**6))
def test_a_deleted_semicolon_is_reported_on_its_line(program: str, which: int) -> None:
    text = format_text(program)  # one statement a line
    assume(text is not None and parse(text).ok)
    offsets = _line_ending_semicolons(text)
    if offsets:
        check_deleted_semicolon(text, offsets[which % len(offsets)])
