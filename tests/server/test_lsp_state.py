"""State and parameters through the real rdcd-lsp over stdio (issue 17): hover, navigation,
highlights, rename, completion, signature help, semantic tokens, symbols, folding, inlay hints
and formatting."""

from __future__ import annotations

from pathlib import Path

import pytest
from lsprotocol import types

from tests.server.conftest import EXAMPLES, Session, doc, position_of
from tests.server.test_lsp_features import apply_edits, hover_text

PROGRAM = (Path(__file__).parent / "data" / "state_names.rdcd").read_text()


def open_program(lsp: Session, name: str, text: str = PROGRAM) -> str:
    uri = f"file:///virtual/state-{name}.rdcd"
    published = lsp.open(uri, text)
    assert not [d for d in published if d.severity == types.DiagnosticSeverity.Error]
    return uri


def test_hover_on_states_parameters_and_neighbours(lsp: Session) -> None:
    uri = open_program(lsp, "hover")
    module = hover_text(lsp, uri, PROGRAM, "neighbours.hops", 12)
    assert "**module state** `hops` := 127" in module and "kept across role changes" in module
    assert "published" in module
    role = hover_text(lsp, uri, PROGRAM, "seen := k", 1)
    assert "**role state** `seen` := 0 of role `Node`" in role and "`Wheel`, `Other`" in role
    parameter = hover_text(lsp, uri, PROGRAM, "turnContinuously(speed)", 18)
    assert "**parameter** `speed`" in parameter and "`Node.turn(speed)`" in parameter
    assert "**neighbours**" in hover_text(lsp, uri, PROGRAM, "neighbours(DOWN)", 2)
    assert "**children**" in hover_text(lsp, uri, PROGRAM, "children.hops", 2)
    assert "count(v: values) -> int" in hover_text(lsp, uri, PROGRAM, "count(", 1)
    assert "min(v: values) -> int" in hover_text(lsp, uri, PROGRAM, "min(a", 1)


def test_navigation_of_role_state_across_sub_roles(lsp: Session) -> None:
    uri = open_program(lsp, "nav")
    use = position_of(PROGRAM, "seen := k", delta=1)
    locations = lsp.request(types.TEXT_DOCUMENT_DEFINITION, types.DefinitionParams(
        text_document=doc(uri), position=use))
    assert [loc.range.start for loc in locations] == [position_of(PROGRAM, "seen := 0")]
    refs = lsp.request(types.TEXT_DOCUMENT_REFERENCES, types.ReferenceParams(
        text_document=doc(uri), position=use, context=types.ReferenceContext(include_declaration=True)))
    assert len(refs) == 5  # declaration, two writes, two reads (one in Wheel)
    highlights = lsp.request(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT, types.DocumentHighlightParams(
        text_document=doc(uri), position=use))
    kinds = sorted(h.kind for h in highlights)
    assert kinds.count(types.DocumentHighlightKind.Write) == 3
    assert kinds.count(types.DocumentHighlightKind.Read) == 2
    parameter = position_of(PROGRAM, "min(a, b)", delta=4)
    locations = lsp.request(types.TEXT_DOCUMENT_DEFINITION, types.DefinitionParams(
        text_document=doc(uri), position=parameter))
    assert locations[0].range.start == position_of(PROGRAM, "a, b)")


def test_rename_state_and_parameter_and_refusal(lsp: Session) -> None:
    uri = open_program(lsp, "rename")
    at = position_of(PROGRAM, "children.hops", delta=10)
    prepared = lsp.request(types.TEXT_DOCUMENT_PREPARE_RENAME, types.PrepareRenameParams(
        text_document=doc(uri), position=at))
    assert prepared is not None and prepared.placeholder == "hops"
    edit = lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(
        text_document=doc(uri), position=at, new_name="distance"))
    renamed = apply_edits(PROGRAM, edit.changes[uri])
    assert "state distance := 127;" in renamed and "children.distance" in renamed
    assert "hops" not in renamed.split("\n", 1)[1]  # every use but the first line's comment
    with pytest.raises(Exception, match="spare"):
        lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(
            text_document=doc(uri), position=at, new_name="spare"))
    parameter = position_of(PROGRAM, "turn(speed)", delta=6)
    edit = lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(
        text_document=doc(uri), position=parameter, new_name="velocity"))
    assert len(edit.changes[uri]) == 2
    with pytest.raises(Exception, match="role state 'seen'"):
        lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(
            text_document=doc(uri), position=parameter, new_name="seen"))


def completion_labels(lsp: Session, uri: str, text: str, needle: str,
                      delta: int) -> dict[str, types.CompletionItem]:
    result = lsp.request(types.TEXT_DOCUMENT_COMPLETION, types.CompletionParams(
        text_document=doc(uri), position=position_of(text, needle, delta=delta)))
    return {item.label: item for item in result.items}


def test_completion_of_states_after_neighbours_and_in_values(lsp: Session) -> None:
    uri = open_program(lsp, "complete")
    edited = PROGRAM.replace("max(children.hops)", "max(neighbours(DOWN).", 1)
    lsp.replace_all(uri, edited)
    found = completion_labels(lsp, uri, edited, "neighbours(DOWN).)", 17)
    assert set(found) == {"hops", "spare"}
    assert found["hops"].kind == types.CompletionItemKind.Variable
    edited = PROGRAM.replace("hops := min(a, b) + spare;", "hops := min(a, b) + ;", 1)
    lsp.replace_all(uri, edited)
    found = completion_labels(lsp, uri, edited, "+ ;", 2)
    assert {"a", "b", "seen", "hops", "spare", "count", "sum"} <= set(found)
    edited = PROGRAM.replace("Node.turn(seen);", "Node.", 1)
    lsp.replace_all(uri, edited)
    found = completion_labels(lsp, uri, edited, "Node.\n", 5)
    assert found["turn"].text_edit.new_text == "turn(${1:speed})"
    assert found["turn"].insert_text_format == types.InsertTextFormat.Snippet


def test_signature_help_for_commands_and_methods(lsp: Session) -> None:
    uri = open_program(lsp, "signature")
    edited = PROGRAM.replace("Node.turn(seen);", "Node.turn(", 1)
    lsp.replace_all(uri, edited)
    help_ = lsp.request(types.TEXT_DOCUMENT_SIGNATURE_HELP, types.SignatureHelpParams(
        text_document=doc(uri), position=position_of(edited, "Node.turn(", delta=10)))
    assert help_ is not None and help_.signatures[0].label == "Node.turn(speed: int)"
    assert help_.signatures[0].parameters[0].label == (10, 20)
    edited = PROGRAM.replace("self.helper(count(neighbours.hops), max(children.hops));", "self.helper(1, ", 1)
    lsp.replace_all(uri, edited)
    help_ = lsp.request(types.TEXT_DOCUMENT_SIGNATURE_HELP, types.SignatureHelpParams(
        text_document=doc(uri), position=position_of(edited, "self.helper(1, ", delta=15)))
    assert help_.signatures[0].label == "self.helper(a: int, b: int)" and help_.active_parameter == 1


def decoded(lsp: Session, uri: str, text: str) -> dict[tuple[int, int], tuple[str, set[str]]]:
    """(line, character) -> (token type, modifiers), from the LSP's relative encoding."""
    legend = lsp.initialize_result.capabilities.semantic_tokens_provider.legend
    data = lsp.request(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
                       types.SemanticTokensParams(text_document=doc(uri))).data
    found = {}
    line = char = 0
    for i in range(0, len(data), 5):
        delta_line, delta_char, _, kind, bits = data[i:i + 5]
        line += delta_line
        char = char + delta_char if delta_line == 0 else delta_char
        modifiers = {m for b, m in enumerate(legend.token_modifiers) if bits & (1 << b)}
        found[(line, char)] = (legend.token_types[kind], modifiers)
    return found


def test_semantic_tokens_of_states_and_parameters(lsp: Session) -> None:
    uri = open_program(lsp, "tokens")
    found = decoded(lsp, uri, PROGRAM)

    def at(needle: str, delta: int = 0) -> tuple[str, set[str]]:
        position = position_of(PROGRAM, needle, delta=delta)
        return found[(position.line, position.character)]

    assert at("hops := 127") == ("variable", {"declaration", "static"})
    assert at("hops := min") == ("variable", {"static", "modification"})
    assert at("seen + 1") == ("variable", set())
    assert at("k := 2") == ("variable", {"declaration", "readonly"})
    assert at("turnContinuously(speed)", 17) == ("parameter", {"readonly"})
    assert at("neighbours(DOWN)") == ("keyword", set())


def test_symbols_folding_inlay_and_formatting_on_the_state_examples(lsp: Session) -> None:
    uri = open_program(lsp, "symbols")
    found = lsp.request(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL,
                        types.DocumentSymbolParams(text_document=doc(uri)))
    assert [(s.name, s.kind) for s in found[:3]] == [("hops", types.SymbolKind.Variable),
                                                    ("spare", types.SymbolKind.Variable),
                                                    ("Node", types.SymbolKind.Class)]
    node = found[2]
    assert (node.children[0].name, node.children[0].kind) == ("seen", types.SymbolKind.Variable)
    assert node.children[1].detail == "command (speed)"
    for name in ("gradient", "count", "lowest"):
        text = (EXAMPLES / f"{name}.rdcd").read_text()
        example = open_program(lsp, f"example-{name}", text)
        folds = lsp.request(types.TEXT_DOCUMENT_FOLDING_RANGE,
                            types.FoldingRangeParams(text_document=doc(example)))
        assert any(f.start_line == position_of(text, "role Node").line for f in folds)
        hints = lsp.request(types.TEXT_DOCUMENT_INLAY_HINT, types.InlayHintParams(
            text_document=doc(example), range=types.Range(start=types.Position(line=0, character=0),
                                                           end=types.Position(line=200, character=0))))
        assert hints and all(h.label.endswith(" B") for h in hints)
        edits = lsp.request(types.TEXT_DOCUMENT_FORMATTING, types.DocumentFormattingParams(
            text_document=doc(example), options=types.FormattingOptions(tab_size=2, insert_spaces=True)))
        assert not edits  # the examples are formatted


def test_formatting_state_over_lsp_is_idempotent(lsp: Session) -> None:
    uri = "file:///virtual/state-format.rdcd"
    text = ("state x:=1; // kept\nrole A{\n state s:=x; // too\n command c(v){s:=v;}\n"
            " behavior b(){x:=sum(children.x);}}\ndeployment{A}\n")
    lsp.open(uri, text)
    options = types.FormattingOptions(tab_size=2, insert_spaces=True)
    edits = lsp.request(types.TEXT_DOCUMENT_FORMATTING, types.DocumentFormattingParams(
        text_document=doc(uri), options=options))
    formatted = apply_edits(text, edits)
    assert "state x := 1; // kept\n" in formatted and "  state s := x; // too\n" in formatted
    assert "  command c(v) {\n    s := v;\n  }\n" in formatted
    lsp.replace_all(uri, formatted)
    again = lsp.request(types.TEXT_DOCUMENT_FORMATTING, types.DocumentFormattingParams(
        text_document=doc(uri), options=options))
    assert not again


def test_code_action_declares_an_unknown_state(lsp: Session) -> None:
    from tests.server.test_lsp_features import code_actions

    uri = "file:///virtual/state-action.rdcd"
    text = "role A {\n  behavior b() { hops := hops + 1; }\n}\ndeployment { A }\n"
    published = lsp.open(uri, text)
    assert "E702" in [d.code for d in published]
    actions = code_actions(lsp, uri, text, published)
    titles = {a.title: a for a in actions}
    assert {"declare module state 'hops'", "declare role state 'hops' in 'A'"} <= set(titles)
    fixed = apply_edits(text, titles["declare module state 'hops'"].edit.changes[uri])
    assert fixed.startswith("state hops := 0;\n\nrole A {")
    assert not [d for d in lsp.replace_all(uri, fixed) or [] if d.severity == types.DiagnosticSeverity.Error]
