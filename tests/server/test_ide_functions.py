"""The IDE features as plain functions over the checked model (no client, no server)."""

from __future__ import annotations

import pytest

from rdcd_core.ide import completion, folding, hover, inlay, navigation, rename, signature, symbols, tokens
from rdcd_core.ide.analysis import Analysis, analyze
from rdcd_core.ide.context import call_context, cursor_context
from tests.server.conftest import EXAMPLES, offset_of

OBSTACLE = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()


@pytest.fixture(scope="module")
def example() -> Analysis:
    return analyze(OBSTACLE)


def at(needle: str, delta: int = 1, nth: int = 0) -> int:
    return offset_of(OBSTACLE, needle, nth, delta)


def test_definition_of_constant_use_is_the_abstract_declaration(example: Analysis) -> None:
    spans = navigation.definition(example, at("turnContinuously(turn_direction)", 20))
    assert [OBSTACLE[s.start:s.end] for s in spans] == ["turn_direction"]
    assert spans[0].start == OBSTACLE.index("turn_direction;")


def test_references_span_the_hierarchy(example: Analysis) -> None:
    spans = navigation.references(example, at("event_handler :="))
    assert len(spans) == OBSTACLE.count("event_handler")
    without = navigation.references(example, at("event_handler :="), include_declaration=False)
    assert len(without) < len(spans)


def test_role_references_include_extends_and_connected_role(example: Analysis) -> None:
    spans = navigation.references(example, at("abstract role Wheel", 15))
    texts = {OBSTACLE[s.start - 8:s.end] for s in spans}
    assert any("extends Wheel" in t for t in texts)
    assert len(spans) == 6  # declaration, 2 extends, modifies, Wheel.stop(), connected_role


def test_highlight_marks_declarations(example: Analysis) -> None:
    marks = navigation.highlights(example, at("Reverse modifies", 1))
    assert sorted(is_def for _, is_def in marks) == [False, False, True]


def test_hover_texts(example: Analysis) -> None:
    role = hover.hover(example, at("role Axle {", 6))
    assert role is not None and "steer" in role.markdown and "Module" in role.markdown
    mixin = hover.hover(example, at("Reverse modifies", 1))
    assert mixin is not None and "modifies `Wheel`" in mixin.markdown
    value = hover.hover(example, at("EVENT_PROXIMITY_5", 2))
    assert value is not None and "`5`" in value.markdown
    assert hover.hover(example, at("deployment", 0)) is None


def test_rename_method_and_refusals(example: Analysis) -> None:
    edits = rename.rename(example, at("stop() {"), "halt")
    assert len(edits) == 2 and {e.new_text for e in edits} == {"halt"}
    with pytest.raises(rename.RenameError):
        rename.rename(example, at("stop() {"), "move")  # Wheel already has a method move
    with pytest.raises(rename.RenameError):
        rename.rename(example, at("turn_direction;"), "event_handler")
    with pytest.raises(rename.RenameError):
        rename.rename(example, at("role Axle {", 6), "role")
    with pytest.raises(rename.RenameError):
        rename.rename(example, at("role Axle {", 6), "9lives")
    assert rename.prepare_rename(example, at("EAST_WEST")) is None
    assert rename.prepare_rename(example, at("self.turnTowards", 7)) is None


def test_rename_constant_everywhere(example: Analysis) -> None:
    edits = rename.rename(example, at("turn_direction :="), "spin")
    assert len(edits) == OBSTACLE.count("turn_direction")


def test_symbols(example: Analysis) -> None:
    found = symbols.document_symbols(example)
    assert [s.name for s in found] == ["Wheel", "RightWheel", "LeftWheel", "Reverse", "Axle", "deployment"]
    wheel = found[0]
    assert [c.name for c in wheel.children] == ["connected_direction", "event_handler", "turn_direction",
                                                 "move()", "stop()"]
    hits = symbols.workspace_symbols({"a": example}, "stop")
    assert [(uri, s.name, c) for uri, s, c in hits] == [("a", "stop()", "Wheel")]


def labels(text: str, offset: int, analysis: Analysis) -> set[str]:
    return {item.label for item in completion.complete(text, offset, analysis.model)[1]}


def test_completion_on_incomplete_text(example: Analysis) -> None:
    broken = OBSTACLE.replace("behavior steer() {", "behavior steer() {\n    self.", 1)
    offset = broken.index("self.\n") + 5
    found = labels(broken, offset, example)
    assert {"turnTowards", "center_position", "setLed"} <= found
    prefixed = broken.replace("self.\n", "self.tur\n", 1)
    assert labels(prefixed, prefixed.index("self.tur\n") + 8, example) == {
        "turnContinuously", "turnTowards", "turnDegrees", "turnQuarters"}


def test_completion_of_own_plain_methods_and_mixin_constants() -> None:
    text = ("role A {\n  constant k := 3;\n  helper() { self.sleep(); }\n"
            "  startup go() { self.helper(); }\n}\ndeployment { A }\n")
    analysis = analyze(text)
    edited = text.replace("self.helper();", "self.", 1)
    found = labels(edited, edited.index("self. }") + 5, analysis)
    assert "helper" in found
    item = next(i for i in completion.complete(edited, edited.index("self. }") + 5, analysis.model)[1]
                if i.label == "turnTowards")
    assert item.insert_text == "turnTowards(${1:deg})"
    expression = text.replace("self.helper();", "self.turnTowards(", 1)
    in_arg = labels(expression, expression.index("turnTowards(") + 12, analysis)
    assert "k" in in_arg and "EAST" not in in_arg


def test_completion_of_role_positions(example: Analysis) -> None:
    text = OBSTACLE + "\nrole New extends "
    assert {"Wheel", "Axle"} <= labels(text, len(text), example)
    assert "Reverse" not in labels(text, len(text), example)
    second = OBSTACLE.replace("connected_role(DOWN, Wheel)", "connected_role(DOWN, ", 1)
    found = labels(second, second.index("connected_role(DOWN, ") + 21, example)
    assert {"Wheel", "Reverse", "Axle"} <= found
    top = labels("", 0, example)
    assert top == {"abstract", "role", "state", "travelling", "deployment"}


def test_cursor_and_call_context() -> None:
    context = cursor_context("role A { startup go() { self.assumeRole(Rev", 44)
    assert context.role == "A" and context.prefix == "Rev"
    assert context.call is not None and (context.call.callee, context.call.arg_index) == ("assumeRole", 0)
    assert call_context("self.handleEvent(E, { self.sleep(); ") is None
    nested = call_context("x(sizeof(self.connected(UP)), ")
    assert nested is not None and (nested.callee, nested.arg_index) == ("x", 1)
    assert cursor_context("/* self. */ ", 12).after_dot is None


def test_signature_help() -> None:
    text = "role A { startup go() { self.turnTowards(1 + "
    info = signature.signature_help(text, len(text))
    assert info is not None and info.label == "self.turnTowards(deg: int) -> void"
    assert info.active_parameter == 0
    start, end = info.parameters[0]
    assert info.label[start:end] == "deg: int"
    second = "x := connected_role(DOWN, "
    info = signature.signature_help(second, len(second))
    assert info is not None and info.active_parameter == 1
    assert signature.signature_help("Wheel.stop(", 11) is None


def test_semantic_tokens(example: Analysis) -> None:
    found = tokens.semantic_tokens(example)
    by_text = {OBSTACLE[t.span.start:t.span.end]: t for t in found}
    assert by_text["Reverse"].type == "interface"
    assert by_text["Wheel"].type == "class"
    assert by_text["turnContinuously"].type == "function"
    assert by_text["EAST"].type == "enumMember"
    assert by_text["role"].type == "keyword" and by_text["30"].type == "number"
    assert by_text["turn_direction"].type == "variable"
    starts = [t.span.start for t in found]
    assert starts == sorted(starts)


def test_folding(example: Analysis) -> None:
    folds = folding.folding_ranges(example)
    lines = {(f.start_line, f.kind) for f in folds}
    assert (0, "comment") in lines  # the three header comment lines
    assert (OBSTACLE[:OBSTACLE.index("abstract role Wheel")].count("\n"), "region") in lines


def test_inlay_hints_mark_budget(example: Analysis) -> None:
    hints = inlay.fragment_hints(example)
    assert hints and all(h.label.endswith("B") or "over" in h.label for h in hints)
    assert not any(h.over_budget for h in hints)
    label, _, over = inlay.label([inlay.FragmentSize("f", "entry", ("A",), ("m",), 60)], 43)
    assert over and "over 43 B" in label


def test_functions_survive_garbage() -> None:
    garbage = analyze("}}}{{ role role ( ; := 99999999999 /* \x00 é 😀")
    for offset in (0, 5, 10, 1000):
        hover.hover(garbage, offset)
        navigation.references(garbage, offset)
        rename.prepare_rename(garbage, offset)
        completion.complete(garbage.text, offset, garbage.model)
        signature.signature_help(garbage.text, offset)
    tokens.semantic_tokens(garbage)
    folding.folding_ranges(garbage)
    symbols.document_symbols(garbage)
    inlay.fragment_hints(garbage)


def test_overrides_and_global_calls_are_one_symbol() -> None:
    text = ("role A {\n  command c() { self.sleep(); }\n  startup s() { A.c(); }\n}\n"
            "role B extends A {\n  command c() { self.setLed(1); }\n}\n"
            "role D {\n  command c() { self.sleep(); }\n}\ndeployment { B, D }\n")
    analysis = analyze(text)
    spans = navigation.references(analysis, text.index("A.c()") + 2)
    assert len(spans) == 3  # A's c, the call, B's override; not D's unrelated c
    assert navigation.definition(analysis, text.index("A.c()") + 2)[0].start == text.index("c()")
    edits = rename.rename(analysis, text.index("c()"), "go")
    assert len(edits) == 3


def test_completion_after_comparison_offers_the_same_type(example: Analysis) -> None:
    text = OBSTACLE.replace("self.center_position == EAST_WEST;", "self.center_position == ", 1)
    found = labels(text, text.index("center_position == ") + 19, example)
    assert {"EAST_WEST", "NORTH_SOUTH", "UP_DOWN"} <= found and "EAST" not in found
