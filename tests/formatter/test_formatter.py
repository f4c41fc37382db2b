"""The formatter: canonical layout, every comment kept, the AST unchanged, idempotent."""

from __future__ import annotations

from pathlib import Path

import pytest

from rdcd_core.formatter import format_range, format_text
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import parse

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def shape(text: str) -> object:
    result = parse(text)
    return ast.strip_spans(result.program)


def comments(text: str) -> list[str]:
    return [c.text for c in parse(text).program.comments]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.rdcd")), ids=lambda p: p.name)
def test_examples_are_stable(path: Path) -> None:
    text = path.read_text()
    once = format_text(text)
    if path.name == "figure5_verbatim.rdcd":
        assert once is None  # it has a syntax error
        return
    assert once is not None
    assert format_text(once) == once
    assert shape(once) == shape(text)
    assert comments(once) == comments(text)


def test_canonical_examples_are_already_formatted() -> None:
    for name in ("obstacle_avoidance.rdcd", "snake_wave.rdcd"):
        text = (EXAMPLES / name).read_text()
        assert format_text(text) == text


def test_messy_program() -> None:
    text = ("abstract   role A{abstract constant x,y;sizeof(self.total_connected())==1;"
            "startup go(){if(x>0)self.turnTowards(x);else{self.sleep();}}}"
            "role B extends A{constant x:=1;constant y:=-2;}"
            "role M modifies A{}\ndeployment{B}")
    expected = """abstract role A {
  abstract constant x, y;
  sizeof(self.total_connected()) == 1;
  startup go() {
    if (x > 0)
      self.turnTowards(x);
    else {
      self.sleep();
    }
  }
}

role B extends A {
  constant x := 1;
  constant y := -2;
}

role M modifies A { }

deployment { B }
"""
    assert format_text(text) == expected


def test_comments_everywhere_are_kept() -> None:
    text = """// head
role A { // after brace
  /* before constant */ constant c := 1 /* inside */ + 2; // trailing
  startup go() {
    // alone
    self.handleEvent(EVENT_PROXIMITY_0, { self.sleep(); /* in block */ });
    if (c > 0) // after condition
      self.sleep();
    else // after else
      self.setLed(c);
    // before close
  }
  // end of role
}
/* between */
deployment { A } // end
// last
"""
    once = format_text(text)
    assert once is not None
    assert comments(once) == comments(text)
    assert shape(once) == shape(text)
    assert format_text(once) == once


def test_syntax_error_gives_none() -> None:
    assert format_text("role A { constant := ; }\ndeployment { A }") is None


def test_range_formatting_touches_only_the_range() -> None:
    text = "role A{constant c:=1;}\n\nrole B{constant d:=2;}\ndeployment{A,B}\n"
    edits = format_range(text, Span(0, 5))
    assert edits
    assert all(e.span.start < text.index("role B") for e in edits)
    full = format_text(text)
    assert full is not None and "role B {" in full
