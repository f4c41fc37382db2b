"""Parsing an edited text with the previous result: the result is that of a fresh parse, and the
roles found unchanged at the same offset are taken over (what keeps the editor fast)."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.syntax import parse
from rdcd_core.syntax.parser import ParseResult
from rdcd_core.syntax.tables import tables
from tests.syntax.fuzz_inputs import EXAMPLES, example_sources

SOURCES = example_sources()
CLEAN = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
SNIPPETS = ["", ";", "}", "{", "self.", "role X { }", "constant k := 3;", "(", ")", "é", "\n", " ",
            "deployment { Axle }", "Wheel", "if (", "//", "/*", "*/", "abstract ", "-1", "x", "=",
            "abstract role Y extends Wheel { }\n"]


def same(a: ParseResult, b: ParseResult) -> bool:
    return a.program == b.program and a.diagnostics == b.diagnostics


def shared_roles(a: ParseResult, b: ParseResult) -> set[int]:
    """The roles that are the same objects in both (ids of objects alive in both)."""
    return {id(role) for role in a.program.roles} & {id(role) for role in b.program.roles}


@given(st.integers(0, len(SOURCES) - 1),
       st.lists(st.tuples(st.floats(0, 1), st.integers(0, 40), st.sampled_from(SNIPPETS)),
                min_size=1, max_size=6))
def test_edited_text_parses_as_if_fresh(which: int, edits: list[tuple[float, int, str]]) -> None:
    text = SOURCES[which]
    previous = parse(text)
    for fraction, length, insert in edits:
        start = int(fraction * len(text))
        text = text[:start] + insert + text[start + length:]
        result = parse(text, previous)
        assert same(result, parse(text))
        if result.ok:
            previous = result


def test_unchanged_roles_are_taken_over() -> None:
    text = CLEAN
    previous = parse(text)
    assert previous.ok
    first, *others = previous.program.roles
    inside = first.span.start + text[first.span.start:].index("{") + 1
    edited = text[:inside] + " " + text[inside + 1:]  # same length: every other role stays put
    result = parse(edited, previous)
    assert same(result, parse(edited))
    assert result.program.roles[0] is not first
    assert all(new is old for new, old in zip(result.program.roles[1:], others, strict=True))


def test_roles_after_an_insertion_are_parsed_again() -> None:
    text = CLEAN
    previous = parse(text)
    edited = "\n" + text
    result = parse(edited, previous)
    assert same(result, parse(edited))
    assert not shared_roles(result, previous)


def test_a_previous_parse_with_errors_is_not_used() -> None:
    text = CLEAN
    broken = parse(text.replace(";", "", 1))
    assert not broken.ok
    result = parse(text, broken)
    assert same(result, parse(text))
    assert not shared_roles(result, broken)


def test_a_role_glued_to_a_new_word_is_not_taken_over() -> None:
    text = "role A { }\nrole B { }\ndeployment { A, B }"
    previous = parse(text)
    edited = text.replace("\nrole B", "xrole B")  # 'xrole' is one name: B is no role any more
    result = parse(edited, previous)
    assert same(result, parse(edited))
    assert not result.ok


def test_the_lexer_lexes_a_stretch_of_the_text() -> None:
    text = "role A { x > 1; } // done"
    lexer = tables().lexer
    whole = lexer.lex(text)
    stretch = lexer.lex(text, 9, 16)
    assert [(t.type, t.start, t.end) for t in stretch.tokens] == \
        [(t.type, t.start, t.end) for t in whole.tokens if 9 <= t.start and t.end <= 16]
    assert [c.span.start for c in lexer.lex(text, 17).comments] == [18]
