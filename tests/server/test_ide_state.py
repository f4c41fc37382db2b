"""The IDE features on state and parameters (issue 17), as plain functions over the checked model:
hover, navigation, highlights, rename, completion, signature help, semantic tokens, symbols,
folding, inlay hints and formatting, on a program with every kind of name and on the examples."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from rdcd_core import formatter
from rdcd_core.ide import completion, folding, hover, inlay, navigation, rename, signature, symbols, tokens
from rdcd_core.ide.analysis import Analysis, analyze
from rdcd_core.ide.context import blank_comments
from tests.server.conftest import EXAMPLES, offset_of

PROGRAM = (Path(__file__).parent / "data" / "state_names.rdcd").read_text()
STATE_EXAMPLES = ("gradient", "count", "lowest")


@pytest.fixture(scope="module")
def names() -> Analysis:
    return analyze(PROGRAM)


def at(needle: str, delta: int = 1, nth: int = 0) -> int:
    return offset_of(PROGRAM, needle, nth, delta)


def words(name: str) -> int:
    """How many times ``name`` occurs as a word outside comments."""
    return len(re.findall(rf"\b{name}\b", blank_comments(PROGRAM)))


def hover_at(analysis: Analysis, offset: int) -> str:
    found = hover.hover(analysis, offset)
    assert found is not None, f"no hover at {offset}"
    return found.markdown


def texts(spans: list) -> list[str]:  # type: ignore[type-arg]
    return [PROGRAM[s.start:s.end] for s in spans]


def test_the_program_checks_without_errors(names: Analysis) -> None:
    assert not names.model.has_errors  # type: ignore[union-attr]
    assert names.compiled() is not None


# -- hover ------------------------------------------------------------------------------------
def test_hover_module_state_at_declaration_and_use(names: Analysis) -> None:
    declared = hover_at(names, at("hops := 127"))
    assert "**module state** `hops` := 127" in declared
    assert "kept across role changes" in declared
    assert "published: neighbours read it" in declared
    assert "assigned in: `Node.helper()`" in declared
    used = hover_at(names, at("neighbours.hops", 12))
    assert used == declared
    spare = hover_at(names, at("+ spare", 3))
    assert "not published" in spare and "assigned in: nowhere" in spare and "5" in spare


def test_hover_role_state_says_where_it_is_reset(names: Analysis) -> None:
    declared = hover_at(names, at("seen := 0"))
    assert "**role state** `seen` := 0 of role `Node`" in declared
    assert "back to 0 whenever the module takes a role that extends `Node` (`Wheel`, `Other`)" in declared
    assert "assigned in: `Node.turn()`, `Wheel.go()`" in declared
    assert "published" not in declared  # role state is never sent to neighbours
    assert hover_at(names, at("seen := k")) == declared  # a use in a sub-role: the same state
    mine = hover_at(names, at("mine := -1"))
    assert "back to -1 whenever the module takes `Other`;" in mine
    concrete = analyze("role A { state n := 2; behavior b() { n := n + 1; } }\n"
                       "role B extends A { self.z() == 0; }\ndeployment { B, A }\n")
    text = hover_at(concrete, concrete.text.index("n :=") + 1)
    assert "back to 2 whenever the module takes `A` or a sub-role (`B`)" in text


def test_hover_parameters(names: Analysis) -> None:
    speed = hover_at(names, at("turnContinuously(speed)", 18))
    assert "**parameter** `speed`: int of command `Node.turn(speed)`" in speed
    assert "argument byte" in speed
    declared = hover_at(names, at("turn(speed)", 6))
    assert declared == speed
    second = hover_at(names, at("min(a, b)", 7))
    assert "of method `Node.helper(a, b)`" in second and "argument 2" in second


def test_hover_commands_and_methods_show_parameters(names: Analysis) -> None:
    call = hover_at(names, at("Node.turn(seen)", 6))
    assert "`Node.turn(speed)`" in call and "called as `Node.turn(speed)`" in call
    assert "`Node.helper(a, b)`" in hover_at(names, at("self.helper(", 6))


def test_hover_neighbours_children_and_aggregates(names: Analysis) -> None:
    neighbours = hover_at(names, at("neighbours.hops", 3))
    assert "**neighbours**" in neighbours and "neighbours(DOWN).s" in neighbours
    assert hover_at(names, at("neighbours(DOWN)", 0)) == neighbours  # at the word's first character
    assert "**children**" in hover_at(names, at("children.hops", 8))  # and at its end
    assert "**state**" in hover_at(names, at("state spare", 2))
    assert hover.hover(names, at("neighbours publish", 2)) is None  # in a comment: no hover
    minimum = hover_at(names, at("min(a", 1))
    assert "min(a: int, b: int) -> int" in minimum and "min(v: values) -> int" in minimum
    assert "127 when none has" in minimum
    assert "count(v: values) -> int" in hover_at(names, at("count(", 2))
    assert "max(v: values)" in hover_at(names, at("max(children", 1))


# -- navigation and highlights ----------------------------------------------------------------
def test_definition_of_states_and_parameters(names: Analysis) -> None:
    assert navigation.definition(names, at("neighbours.hops", 12))[0].start == PROGRAM.index("hops :=")
    role_state = navigation.definition(names, at("seen := k"))  # Wheel uses Node's role state
    assert [s.start for s in role_state] == [PROGRAM.index("seen := 0")]
    parameter = navigation.definition(names, at("turnContinuously(speed)", 18))
    assert [s.start for s in parameter] == [PROGRAM.index("speed)")]
    assert navigation.definition(names, at("min(a, b)", 4))[0].start == PROGRAM.index("a, b)")


@pytest.mark.parametrize("name, needle", [
    ("hops", "hops := min"), ("spare", "+ spare"), ("seen", "seen := k"), ("mine", "mine + min"),
])
def test_references_of_states_cover_every_use(names: Analysis, name: str, needle: str) -> None:
    offset = PROGRAM.index(needle) + needle.index(name) + 1
    found = navigation.references(names, offset)
    assert texts(found) == [name] * words(name)
    without = navigation.references(names, offset, include_declaration=False)
    assert len(without) == len(found) - 1


def test_references_of_parameters_stay_in_their_method(names: Analysis) -> None:
    assert len(navigation.references(names, at("turnContinuously(speed)", 18))) == 2
    assert len(navigation.references(names, at("helper(a", 7))) == 2  # not the other methods' names


def test_highlights_mark_declarations_and_assignments_as_writes(names: Analysis) -> None:
    marks = navigation.highlights(names, at("seen := seen", 10))
    writes = sorted(PROGRAM[s.start:s.start + 12] for s, write in marks if write)
    reads = sorted(PROGRAM[s.start:s.start + 12] for s, write in marks if not write)
    assert writes == ["seen := 0; /", "seen := k;\n ", "seen := seen"]
    assert reads == ["seen + 1;\n  ", "seen);\n  }\n}"]


# -- rename -----------------------------------------------------------------------------------
def renamed(analysis: Analysis, offset: int, new_name: str) -> str:
    edits = rename.rename(analysis, offset, new_name)
    text = analysis.text
    for edit in sorted(edits, key=lambda e: e.span.start, reverse=True):
        text = text[:edit.span.start] + edit.new_text + text[edit.span.end:]
    return text


def codes(text: str) -> list[str]:
    return [d.code for d in analyze(text).diagnostics]


@pytest.mark.parametrize("needle, old, new", [
    ("hops := 127", "hops", "distance"),  # module state, from its declaration
    ("children.hops", "hops", "distance"),  # and from a neighbours' read
    ("seen := k", "seen", "visits"),  # role state, from a sub-role
    ("mine := -1", "mine", "k"),  # Wheel's constant k is not visible in Other
    ("speed)", "speed", "a"),  # another method's parameter name is free
    ("speed)", "speed", "k"),  # Node (where turn is declared) has no constant k
    ("b) {", "b", "second"),
])
def test_rename_state_and_parameter_everywhere(names: Analysis, needle: str, old: str, new: str) -> None:
    offset = PROGRAM.index(needle) + needle.index(old) + 1
    assert rename.prepare_rename(names, offset) is not None
    before = len(navigation.references(names, offset))
    text = renamed(names, offset, new)
    assert len(rename.rename(names, offset, new)) == before
    assert codes(text) == codes(PROGRAM)  # the renamed program means the same
    moved = needle[:needle.index(old)] + new + needle[needle.index(old) + len(old):]
    after = analyze(text)
    assert len(navigation.references(after, text.index(moved) + needle.index(old) + 1)) == before


@pytest.mark.parametrize("needle, old, new, reason", [
    ("hops := 127", "hops", "spare", "module state named 'spare'"),
    ("hops := 127", "hops", "k", "role 'Wheel' already has a member named 'k'"),
    ("hops := 127", "hops", "seen", "already has a member named 'seen'"),
    ("hops := 127", "hops", "mine", "role 'Other' already has a member named 'mine'"),
    ("hops := 127", "hops", "turn", "already has a member named 'turn'"),
    ("hops := 127", "hops", "speed", "has a parameter named 'speed'"),
    ("hops := 127", "hops", "min", "Module API function"),
    ("hops := 127", "hops", "Node", "is a role"),
    ("hops := 127", "hops", "state", "reserved"),
    ("hops := 127", "hops", "neighbours", "reserved"),
    ("seen := 0", "seen", "mine", "role 'Other' already has a member named 'mine'"),
    ("seen := 0", "seen", "hops", "module state named 'hops'"),
    ("seen := 0", "seen", "k", "role 'Wheel' already has a member named 'k'"),
    ("speed)", "speed", "seen", "hide the role state 'seen'"),
    ("speed)", "speed", "hops", "hide the module state 'hops'"),
    ("a, b", "a", "b", "already has a parameter named 'b'"),
    ("k := 2", "k", "hops", "module state named 'hops'"),
    ("k := 2", "k", "seen", "already has a member named 'seen'"),
    ("role Other", "Other", "hops", "a state named 'hops'"),
    ("role Other", "Other", "seen", "a state named 'seen'"),
])
def test_rename_refuses_clashes(names: Analysis, needle: str, old: str, new: str, reason: str) -> None:
    offset = PROGRAM.index(needle) + needle.index(old) + 1
    with pytest.raises(rename.RenameError, match=re.escape(reason)):
        rename.rename(names, offset, new)


def test_rename_constant_refuses_a_parameter_that_would_hide_it() -> None:
    text = ("role A {\n  constant c := 1;\n  command go(v) { self.setLed(c + v); }\n}\n"
            "deployment { A }\n")
    analysis = analyze(text)
    with pytest.raises(rename.RenameError, match="parameter named 'v'"):
        rename.rename(analysis, text.index("c :="), "v")


# -- completion -------------------------------------------------------------------------------
def complete_at(text: str, offset: int, analysis: Analysis) -> dict[str, completion.CompletionItem]:
    return {item.label: item for item in completion.complete(text, offset, analysis.model)[1]}


def test_completion_offers_states_and_parameters_where_a_value_is_expected(names: Analysis) -> None:
    edited = PROGRAM.replace("hops := min(a, b) + spare;", "hops := min(a, b) + ", 1)
    found = complete_at(edited, edited.index("+ \n") + 2, names)
    assert {"a", "b", "hops", "spare", "seen"} <= set(found)
    assert found["a"].kind == "parameter" and found["seen"].kind == "state"
    assert found["seen"].detail == "role state of Node := 0" and found["hops"].detail == "module state := 127"
    assert "speed" not in found and "mine" not in found and "k" not in found  # other methods and roles
    in_other = PROGRAM.replace("mine := mine + ", "mine := mine + m", 1)
    offset = in_other.index("mine + m") + 8
    assert {"mine", "min", "max"} <= set(complete_at(in_other, offset, names))


@pytest.mark.parametrize("before", ["neighbours.", "children.", "neighbours(DOWN).", "neighbours( 3 ). "])
def test_completion_after_neighbours_offers_module_state_only(names: Analysis, before: str) -> None:
    edited = PROGRAM.replace("max(children.hops)", f"max({before}", 1)
    offset = edited.index(before) + len(before)
    assert set(complete_at(edited, offset, names)) == {"hops", "spare"}
    prefixed = edited[:offset] + "sp" + edited[offset:]
    assert set(complete_at(prefixed, offset + 2, names)) == {"spare"}


def test_completion_inside_aggregates_offers_neighbours_and_children(names: Analysis) -> None:
    edited = PROGRAM.replace("count(neighbours.hops)", "count(", 1)
    offset = edited.index("count(") + 6
    assert set(complete_at(edited, offset, names)) == {"neighbours", "children"}
    edited = PROGRAM.replace("max(children.hops)", "min(", 1)
    found = complete_at(edited, edited.index("hops), min(") + 11, names)
    assert {"neighbours", "children", "hops", "seen"} <= set(found)
    assert found["neighbours"].insert_text == "neighbours."


def test_completion_of_state_keyword_and_new_functions(names: Analysis) -> None:
    top = {item.label for item in completion.complete("", 0, None)[1]}
    assert "state" in top
    inside = PROGRAM.replace("  state mine := -1;\n", "  \n", 1)
    offset = inside.index("role Other extends Node {\n  ") + len("role Other extends Node {\n  ")
    found = complete_at(inside, offset, names)
    assert "state" in found and found["state"].kind == "keyword"
    body = PROGRAM.replace("    seen := k;\n", "    \n", 1)
    offset = body.index("go() {\n    ") + len("go() {\n    ")
    found = complete_at(body, offset, names)
    assert {"min", "max", "count", "sum", "seen", "hops"} <= set(found)
    assert found["count"].insert_text == "count(${1:v})"


def test_completion_of_commands_and_methods_with_parameters(names: Analysis) -> None:
    edited = PROGRAM.replace("Node.turn(seen);", "Node.", 1)
    found = complete_at(edited, edited.index("Node.\n") + 5, names)
    assert found["turn"].insert_text == "turn(${1:speed})"
    edited = PROGRAM.replace("self.helper(count", "self.hel(count", 1)
    found = complete_at(edited, edited.index("self.hel") + 8, names)
    assert found["helper"].insert_text == "helper(${1:a}, ${2:b})"


# -- signature help ---------------------------------------------------------------------------
def test_signature_help_for_commands_with_arguments(names: Analysis) -> None:
    text = PROGRAM.replace("Node.turn(seen);", "Node.turn(", 1)
    info = signature.signature_help(text, text.index("Node.turn(") + 10, names.model)
    assert info is not None and info.label == "Node.turn(speed: int)"
    start, end = info.parameters[0]
    assert info.label[start:end] == "speed: int" and info.active_parameter == 0
    assert "argument byte" in info.doc
    assert signature.signature_help(text, text.index("Node.turn(") + 10) is None  # no model yet
    assert signature.signature_help(text, text.index("Node.turn(") + 10, None) is None


def test_signature_help_for_methods_with_parameters(names: Analysis) -> None:
    text = PROGRAM.replace("self.helper(count(neighbours.hops), max(children.hops));", "self.helper(1, ", 1)
    info = signature.signature_help(text, text.index("self.helper(1, ") + 15, names.model)
    assert info is not None and info.label == "self.helper(a: int, b: int)"
    assert info.active_parameter == 1
    assert [info.label[a:b] for a, b in info.parameters] == ["a: int", "b: int"]
    # inside an aggregate in an argument: the innermost call (the Module API's min)
    nested = text.replace("self.helper(1, ", "self.helper(min(", 1)
    inner = signature.signature_help(nested, nested.index("helper(min(") + 11, names.model)
    assert inner is not None and inner.label.startswith("min(")


# -- semantic tokens --------------------------------------------------------------------------
def test_semantic_tokens_tell_states_parameters_and_constants_apart(names: Analysis) -> None:
    found = tokens.semantic_tokens(names)

    def token(needle: str, delta: int = 0) -> tokens.Token:
        start = PROGRAM.index(needle) + delta
        return next(t for t in found if t.span.start == start)

    declared = token("hops := 127")
    assert (declared.type, declared.modifiers) == ("variable", ("declaration", "static"))
    assert token("hops := min").modifiers == ("static", "modification")
    assert token("neighbours.hops", 11).modifiers == ("static",)
    assert (token("seen := 0").type, token("seen := 0").modifiers) == ("variable", ("declaration",))
    assert token("seen + 1").modifiers == ()  # a role state read: neither readonly nor static
    assert token("seen := seen").modifiers == ("modification",)
    assert token("speed)").type == "parameter" and "declaration" in token("speed)").modifiers
    assert token("k := 2").modifiers == ("declaration", "readonly")  # constants stay readonly
    assert token("neighbours.hops").type == "keyword" and token("children.").type == "keyword"
    assert token("state hops").type == "keyword"
    # the legend only grows at its end: clients that cached the old indices stay right
    assert tokens.TOKEN_TYPES[:10] == ("class", "interface", "variable", "method", "function", "enumMember",
                                       "keyword", "number", "comment", "operator")
    assert tokens.TOKEN_MODIFIERS[:4] == ("declaration", "readonly", "abstract", "defaultLibrary")


# -- symbols, folding, inlay hints, formatting ------------------------------------------------
def test_document_symbols_place_states(names: Analysis) -> None:
    found = symbols.document_symbols(names)
    assert [(s.name, s.kind) for s in found] == [
        ("hops", "state"), ("spare", "state"), ("Node", "role"), ("Wheel", "role"), ("Other", "role"),
        ("deployment", "deployment")]
    assert found[0].detail == "module state := 127"
    node = found[2]
    assert [(c.name, c.detail) for c in node.children] == [
        ("seen", "role state := 0"), ("turn()", "command (speed)"), ("helper()", "method (a, b)"),
        ("spread()", "behavior")]
    assert [(c.name, c.detail) for c in found[4].children] == [("mine", "role state := -1"),
                                                               ("tick()", "behavior")]
    hits = symbols.workspace_symbols({"u": names}, "seen")
    assert [(uri, s.name, container) for uri, s, container in hits] == [("u", "seen", "Node")]


def test_module_state_between_roles_stays_in_text_order() -> None:
    text = "role A { startup go() { x := 1; } }\nstate x := 0;\ndeployment { A }\n"
    assert [s.name for s in symbols.document_symbols(analyze(text))] == ["A", "x", "deployment"]


@pytest.mark.parametrize("name", STATE_EXAMPLES)
def test_folding_and_inlay_hints_on_the_state_examples(name: str) -> None:
    text = (EXAMPLES / f"{name}.rdcd").read_text()
    analysis = analyze(text)
    assert not analysis.model.has_errors  # type: ignore[union-attr]
    folds = folding.folding_ranges(analysis)
    assert (0, "comment") in {(f.start_line, f.kind) for f in folds}  # the header comment
    for role in analysis.program.roles:  # type: ignore[union-attr]
        assert any(f.start_line == text.count("\n", 0, role.span.start) for f in folds), role.name.text
    hints = inlay.fragment_hints(analysis)
    assert hints and not any(h.over_budget for h in hints)
    assert all(re.fullmatch(r"\d+ B( \+ \d+ B)*", h.label) for h in hints)


@pytest.mark.parametrize("name", STATE_EXAMPLES)
def test_state_examples_are_formatted_and_formatting_is_idempotent(name: str) -> None:
    text = (EXAMPLES / f"{name}.rdcd").read_text()
    assert formatter.format_text(text) == text


MESSY = """// head
state   x:=1;  // after x
/* before y */ state y := -2;
role A{
  // before s
  state s:=x+1;   // after s
  command c( v ){ s:=v; x := s+y; }
  h(p,q){x:=max(p,q);}
  behavior b(){ self.h(sum(children.x), count(neighbours( DOWN ).x)); }
}
// before deployment
deployment{A}
"""


def test_formatting_state_keeps_comments_and_is_idempotent() -> None:
    once = formatter.format_text(MESSY)
    assert once is not None and formatter.format_text(once) == once
    for comment in ("// head", "// after x", "/* before y */", "// before s", "// after s",
                    "// before deployment"):
        assert comment in once
    assert "state x := 1; // after x" in once and "  state s := x + 1; // after s" in once
    assert "command c(v) {" in once and "count(neighbours(DOWN).x)" in once
    assert codes(once) == codes(MESSY)
    assert formatter.format_text(PROGRAM) == PROGRAM


def test_state_features_survive_broken_state_text() -> None:
    for text in ("state", "state x", "state x :=", "state := 1;", "role A { state", "x := ;",
                 "role A { command c(v { v := ; } }", "min(neighbours.", "role A { b() { neighbours(",
                 "state s := 1; role A { startup go() { s := s + ; } }"):
        analysis = analyze(text)
        for offset in range(len(text) + 1):
            hover.hover(analysis, offset)
            navigation.highlights(analysis, offset)
            rename.prepare_rename(analysis, offset)
            completion.complete(text, offset, analysis.model)
            signature.signature_help(text, offset, analysis.model)
        tokens.semantic_tokens(analysis)
        symbols.document_symbols(analysis)
        folding.folding_ranges(analysis)
        inlay.fragment_hints(analysis)


# -- code actions and naming positions ---------------------------------------------------------
def fixed_by(text: str, title: str) -> str:
    from rdcd_core.ide import actions
    from rdcd_core.source import Span

    found = [a for a in actions.code_actions(analyze(text), Span(0, len(text))) if a.title == title]
    assert len(found) == 1, [a.title for a in actions.code_actions(analyze(text), Span(0, len(text)))]
    for edit in sorted(found[0].fix.edits, key=lambda e: e.span.start, reverse=True):
        text = text[:edit.span.start] + edit.new_text + text[edit.span.end:]
    return text


UNDECLARED = "// A counter.\nrole A {\n    behavior b() { hops := hops + 1; }\n}\ndeployment { A }\n"


def test_code_actions_declare_an_unknown_state() -> None:
    assert "E702" in codes(UNDECLARED)
    module = fixed_by(UNDECLARED, "declare module state 'hops'")
    assert module.startswith("// A counter.\nstate hops := 0;\n\nrole A {")
    assert "E702" not in codes(module) and not analyze(module).model.has_errors  # type: ignore[union-attr]
    role = fixed_by(UNDECLARED, "declare role state 'hops' in 'A'")
    assert "role A {\n    state hops := 0;\n    behavior b()" in role  # the members' indentation
    assert not analyze(role).model.has_errors  # type: ignore[union-attr]
    beside = "state x := 1;\n" + UNDECLARED.replace("hops + 1", "x", 1)
    assert fixed_by(beside, "declare module state 'hops'").startswith("state x := 1;\nstate hops := 0;\n")


def test_code_actions_do_not_declare_state_in_a_mixin() -> None:
    from rdcd_core.ide import actions
    from rdcd_core.source import Span

    text = ("role W { startup s() { self.assumeRole(M, { self.sleep(); }); } }\n"
            "role M modifies W { startup t() { n := 1; } }\ndeployment { W }\n")
    titles = [a.title for a in actions.code_actions(analyze(text), Span(0, len(text)))]
    assert "declare module state 'n'" in titles and not any("role state" in t for t in titles)


def test_completion_where_a_state_is_named_or_initialised(names: Analysis) -> None:
    text = PROGRAM.replace("  constant k := 2;\n", "  constant k := 2;\n  state fresh := \n", 1)
    offset = text.index("fresh := ") + len("fresh := ")
    assert set(complete_at(text, offset, names)) == {"k"}  # a constant int: no state, no parameter
    text = PROGRAM.replace("  constant k := 2;\n", "  constant k := 2;\n  state \n", 1)
    assert complete_at(text, text.index("state \n") + 6, names) == {}


def test_neighbours_filter_completion_and_signature(names: Analysis) -> None:
    edited = PROGRAM.replace("max(children.hops)", "max(neighbours(", 1)
    offset = edited.index("max(neighbours(") + 15
    found = complete_at(edited, offset, names)
    assert {"DOWN", "UP", "EAST"} <= set(found) and "hops" not in found and "EAST_WEST" not in found
    info = signature.signature_help(edited, offset, names.model)
    assert info is not None and info.label.startswith("neighbours(")
    start, end = info.parameters[0]
    assert info.label[start:end] == "where: dir | connector 0..7"


def test_completion_after_comparison_with_a_state(names: Analysis) -> None:
    behaviour = "self.z() == 0;\n  behavior w() { if (seen == ) self.sleep(); }"
    edited = PROGRAM.replace("self.z() == 0;", behaviour, 1)
    found = complete_at(edited, edited.index("seen == ") + 8, names)
    assert {"seen", "hops", "k"} <= set(found) and "EAST" not in found  # ints only


def test_parameters_are_found_after_connected_role_in_the_body() -> None:
    text = ("role A {\n  command go(v) {\n    if (sizeof(connected_role(DOWN, A)) > 0)\n"
            "      self.turnContinuously(\n  }\n}\ndeployment { A }\n")
    offset = text.index("turnContinuously(") + 17
    found = {i.label for i in completion.complete(text, offset, analyze(text).model)[1]}
    assert "v" in found


def test_no_parameters_inside_an_event_handler() -> None:
    text = ("role A {\n  command go(v) {\n    self.setLed(1);\n"
            "    self.handleEvent(EVENT_PROXIMITY_0, { self.turnContinuously( });\n"
            "    self.turnContinuously(\n  }\n}\ndeployment { A }\n")
    model = analyze(text).model
    inside = {i.label for i in completion.complete(text, text.index("turnContinuously( }") + 17, model)[1]}
    after = {i.label for i in completion.complete(text, text.rindex("turnContinuously(") + 17, model)[1]}
    assert "v" not in inside and "v" in after
