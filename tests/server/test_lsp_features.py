"""Every LSP feature of rdcd-lsp, over stdio, on the examples and on small programs."""

from __future__ import annotations

from pathlib import Path

import pytest
from lsprotocol import types

from rdcd_core.frontend import check_text
from tests.server.conftest import EXAMPLES, Session, doc, position_of

OBSTACLE = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()
URI = "file:///virtual/obstacle_avoidance.rdcd"


def open_example(lsp: Session, name: str = "obstacle") -> tuple[str, str]:
    uri = f"file:///virtual/{name}.rdcd"
    lsp.open(uri, OBSTACLE)
    return uri, OBSTACLE


def hover_text(lsp: Session, uri: str, text: str, needle: str, delta: int) -> str:
    """The markdown of the hover at ``needle`` (plus ``delta`` characters)."""
    hover = lsp.request(types.TEXT_DOCUMENT_HOVER, types.HoverParams(
        text_document=doc(uri), position=position_of(text, needle, delta=delta)))
    return hover.contents.value


def test_capabilities(lsp: Session) -> None:
    caps = lsp.initialize_result.capabilities
    assert caps.hover_provider and caps.definition_provider and caps.references_provider
    assert caps.rename_provider and caps.completion_provider and caps.signature_help_provider
    assert caps.semantic_tokens_provider and caps.folding_range_provider and caps.inlay_hint_provider
    assert caps.document_formatting_provider and caps.document_range_formatting_provider
    assert set(caps.execute_command_provider.commands) >= {"rdcd.simulate", "rdcd.showBytecode"}
    assert caps.text_document_sync.change == types.TextDocumentSyncKind.Incremental


def test_diagnostics_match_check_text(lsp: Session) -> None:
    for path in sorted(EXAMPLES.glob("*.rdcd")):
        text = path.read_text()
        uri = f"file:///virtual/diag-{path.name}"
        published = lsp.open(uri, text)
        expected = check_text(text).diagnostics
        assert [d.code for d in published] == [d.code for d in expected]
        assert len(published) == len(expected)


def test_diagnostic_has_range_code_and_related(lsp: Session) -> None:
    text = "role A { constant c := 1; constant c := 2; }\ndeployment { A }\n"
    published = lsp.open("file:///virtual/dup.rdcd", text)
    assert published, "a duplicate member is an error"
    expected = check_text(text).diagnostics
    first = published[0]
    assert first.code == expected[0].code and first.source == "rdcd"
    assert first.range.start.line == 0


def test_hover_role(lsp: Session) -> None:
    uri, text = open_example(lsp, "hover")
    value = hover_text(lsp, uri, text, "RightWheel", 2)
    assert "RightWheel" in value and "Wheel" in value and "Module" in value
    assert "turn_direction" in value and "move" in value
    assert "fragments" in value and "discover_RightWheel_LeftWheel" in value


def test_hover_constant_value_per_role(lsp: Session) -> None:
    uri, text = open_example(lsp, "hover-constant")
    value = hover_text(lsp, uri, text, "turnContinuously(turn_direction)", 20)
    assert "RightWheel" in value and "LeftWheel" in value and "-1" in value


def test_hover_primitive_and_predefined(lsp: Session) -> None:
    uri, text = open_example(lsp, "hover-api")
    assert "turnContinuously(v: int)" in hover_text(lsp, uri, text, "turnContinuously", 3)
    value = hover_text(lsp, uri, text, "EAST_WEST", 1)
    assert "axis" in value and "1" in value


def test_definition_references_highlight(lsp: Session) -> None:
    uri, text = open_example(lsp, "nav")
    use = position_of(text, "self.turnContinuously(turn_direction)", delta=24)
    locations = lsp.request(types.TEXT_DOCUMENT_DEFINITION, types.DefinitionParams(
        text_document=doc(uri), position=use))
    assert locations and locations[0].range.start == position_of(text, "turn_direction;")
    refs = lsp.request(types.TEXT_DOCUMENT_REFERENCES, types.ReferenceParams(
        text_document=doc(uri), position=use, context=types.ReferenceContext(include_declaration=True)))
    assert len(refs) == text.count("turn_direction")
    highlights = lsp.request(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT, types.DocumentHighlightParams(
        text_document=doc(uri), position=use))
    assert len(highlights) == len(refs)


def test_command_navigation_through_global_call(lsp: Session) -> None:
    uri, text = open_example(lsp, "nav-command")
    call = position_of(text, "Wheel.stop()", delta=7)
    locations = lsp.request(types.TEXT_DOCUMENT_DEFINITION, types.DefinitionParams(
        text_document=doc(uri), position=call))
    assert locations[0].range.start == position_of(text, "stop() {")
    refs = lsp.request(types.TEXT_DOCUMENT_REFERENCES, types.ReferenceParams(
        text_document=doc(uri), position=call, context=types.ReferenceContext(include_declaration=True)))
    assert len(refs) == 2


def test_rename_role_and_refusal(lsp: Session) -> None:
    uri, text = open_example(lsp, "rename")
    at = position_of(text, "Wheel {", delta=1)
    prepared = lsp.request(types.TEXT_DOCUMENT_PREPARE_RENAME, types.PrepareRenameParams(
        text_document=doc(uri), position=at))
    assert prepared is not None
    edit = lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(
        text_document=doc(uri), position=at, new_name="Roller"))
    edits = edit.changes[uri]
    import re

    assert len(edits) == len(re.findall(r"\bWheel\b", text))
    try:
        lsp.request(types.TEXT_DOCUMENT_RENAME, types.RenameParams(
            text_document=doc(uri), position=at, new_name="Axle"))
    except Exception as error:  # the server answers with an error: the name clashes
        assert "Axle" in str(error)
    else:
        raise AssertionError("a clashing rename must be refused")


def test_document_and_workspace_symbols(lsp: Session) -> None:
    uri, text = open_example(lsp, "symbols")
    symbols = lsp.request(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL,
                          types.DocumentSymbolParams(text_document=doc(uri)))
    names = [s.name for s in symbols]
    assert names[:5] == ["Wheel", "RightWheel", "LeftWheel", "Reverse", "Axle"]
    assert "move()" in [c.name for c in symbols[0].children]
    found = lsp.request(types.WORKSPACE_SYMBOL, types.WorkspaceSymbolParams(query="wheel"))
    assert any(s.name == "LeftWheel" and s.location.uri == uri for s in found)


def test_completion_after_self_on_incomplete_text(lsp: Session) -> None:
    uri, text = open_example(lsp, "complete-self")
    marker = "    self.turnContinuously(turn_direction);\n  }\n  command"
    broken = text.replace(marker, "    self.\n" + marker, 1)
    lsp.replace_all(uri, broken)
    result = lsp.request(types.TEXT_DOCUMENT_COMPLETION, types.CompletionParams(
        text_document=doc(uri), position=position_of(broken, "self.\n", delta=5)))
    labels = {item.label for item in result.items}
    assert {"turnContinuously", "handleEvent", "center_position", "assumeRole"} <= labels
    snippet = next(i for i in result.items if i.label == "turnTowards")
    assert snippet.insert_text_format == types.InsertTextFormat.Snippet


def test_completion_contexts(lsp: Session) -> None:
    uri, text = open_example(lsp, "complete-ctx")

    def labels_at(position: types.Position) -> set[str]:
        result = lsp.request(types.TEXT_DOCUMENT_COMPLETION, types.CompletionParams(
            text_document=doc(uri), position=position))
        return {item.label for item in result.items}

    assert labels_at(position_of(text, "Wheel.stop", delta=6)) == {"stop"}
    assert "Wheel" in labels_at(position_of(text, "extends Wheel", delta=8))
    assumed = labels_at(position_of(text, "assumeRole(Reverse", delta=11))
    assert assumed == {"Reverse"}
    deployed = labels_at(position_of(text, "deployment { ", delta=13))
    assert {"RightWheel", "LeftWheel", "Axle"} <= deployed and "Wheel" not in deployed
    handler = labels_at(position_of(text, "handleEvent(event_handler", delta=12))
    assert "event_handler" in handler and "EVENT_PROXIMITY_3" in handler and "EAST" not in handler


def test_signature_help(lsp: Session) -> None:
    uri, text = open_example(lsp, "signature")
    help_ = lsp.request(types.TEXT_DOCUMENT_SIGNATURE_HELP, types.SignatureHelpParams(
        text_document=doc(uri), position=position_of(text, "{ self.disableEvent", delta=-1)))
    assert help_.signatures[0].label.startswith("self.handleEvent(")
    assert help_.active_parameter == 1


def test_semantic_tokens_and_folding(lsp: Session) -> None:
    uri, text = open_example(lsp, "tokens")
    tokens = lsp.request(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
                         types.SemanticTokensParams(text_document=doc(uri)))
    assert len(tokens.data) % 5 == 0 and len(tokens.data) > 100
    legend = lsp.initialize_result.capabilities.semantic_tokens_provider.legend.token_types
    kinds = {legend[tokens.data[i + 3]] for i in range(0, len(tokens.data), 5)}
    assert {"class", "interface", "variable", "function", "enumMember", "keyword", "number"} <= kinds
    folds = lsp.request(types.TEXT_DOCUMENT_FOLDING_RANGE, types.FoldingRangeParams(text_document=doc(uri)))
    assert any(f.start_line == position_of(text, "abstract role Wheel").line for f in folds)


def test_formatting(lsp: Session) -> None:
    uri = "file:///virtual/format.rdcd"
    text = "role A{constant c:=1+2;startup go(){self.turnTowards(c);}}\ndeployment{A}\n"
    lsp.open(uri, text)
    edits = lsp.request(types.TEXT_DOCUMENT_FORMATTING, types.DocumentFormattingParams(
        text_document=doc(uri), options=types.FormattingOptions(tab_size=2, insert_spaces=True)))
    assert edits and "constant c := 1 + 2;" in "".join(e.new_text for e in edits)
    ranged = lsp.request(types.TEXT_DOCUMENT_RANGE_FORMATTING, types.DocumentRangeFormattingParams(
        text_document=doc(uri), range=types.Range(start=types.Position(line=1, character=0),
                                                   end=types.Position(line=1, character=5)),
        options=types.FormattingOptions(tab_size=2, insert_spaces=True)))
    assert ranged and all(e.range.start.line >= 1 for e in ranged)


def code_actions(lsp: Session, uri: str, text: str, published: list) -> list[types.CodeAction]:
    lines = text.count("\n") + 1
    return lsp.request(types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionParams(
        text_document=doc(uri), range=types.Range(start=types.Position(line=0, character=0),
                                                   end=types.Position(line=lines, character=0)),
        context=types.CodeActionContext(diagnostics=published)))


def apply_edits(text: str, edits: list[types.TextEdit]) -> str:
    def offset(position: types.Position) -> int:
        return sum(len(line) + 1 for line in text.split("\n")[:position.line]) + position.character

    for edit in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character), reverse=True):
        text = text[:offset(edit.range.start)] + edit.new_text + text[offset(edit.range.end):]
    return text


@pytest.mark.parametrize("text, title", [
    ("role A {\n  abstract constant c;\n}\nrole B extends A {\n  constant c := 1;\n}\ndeployment { B }\n",
     "declare 'A' abstract"),
    ("abstract role W { abstract constant k; }\nrole R extends W { }\ndeployment { R }\n",
     "add the missing constant definitions"),
    ("role A { startup go() { self.turnTowrds(10); } }\ndeployment { A }\n", "replace with 'turnTowards'"),
    ("role A { sizeof(connected_role(DOWN, B)) > 0; }\nrole B { self.y() > 0; }\ndeployment { A, B }\n",
     "reorder the deployment"),
])
def test_code_action_fixes_the_diagnostic(lsp: Session, text: str, title: str) -> None:
    uri = f"file:///virtual/actions-{abs(hash((text, title)))}.rdcd"
    published = lsp.open(uri, text)
    expected = check_text(text).diagnostics
    actions = code_actions(lsp, uri, text, published)
    assert len(actions) == sum(len(d.fixes) for d in expected)
    action = next(a for a in actions if a.title == title)
    assert action.kind == types.CodeActionKind.QuickFix and action.diagnostics
    fixed_code = action.diagnostics[0].code
    fixed = apply_edits(text, action.edit.changes[uri])
    assert fixed_code not in [d.code for d in check_text(fixed).diagnostics]


def test_inlay_hints_fragment_sizes(lsp: Session) -> None:
    uri, text = open_example(lsp, "inlay")
    hints = lsp.request(types.TEXT_DOCUMENT_INLAY_HINT, types.InlayHintParams(
        text_document=doc(uri), range=types.Range(start=types.Position(line=0, character=0),
                                                   end=types.Position(line=200, character=0))))
    assert hints, "the compiled example has fragments"
    assert all("B" in h.label for h in hints)


def test_inlay_hints_can_be_turned_off(tmp_path: Path) -> None:
    (tmp_path / "nested").mkdir()
    (tmp_path / "nested" / "closed.rdcd").write_text("role OnDisk { }\ndeployment { OnDisk }\n")
    session = Session(init_options={"rdcd": {"inlayHints": {"fragmentSizes": False}}},
                      root_uri=tmp_path.as_uri())
    try:
        uri = "file:///virtual/off.rdcd"
        session.open(uri, OBSTACLE)
        hints = session.request(types.TEXT_DOCUMENT_INLAY_HINT, types.InlayHintParams(
            text_document=doc(uri), range=types.Range(start=types.Position(line=0, character=0),
                                                       end=types.Position(line=200, character=0))))
        assert not hints
        session.client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
            settings={"rdcd.inlayHints.fragmentSizes": True}))
        hints = session.request(types.TEXT_DOCUMENT_INLAY_HINT, types.InlayHintParams(
            text_document=doc(uri), range=types.Range(start=types.Position(line=0, character=0),
                                                       end=types.Position(line=200, character=0))))
        assert hints
        found = session.request(types.WORKSPACE_SYMBOL, types.WorkspaceSymbolParams(query="ondisk"))
        assert [s.name for s in found] == ["OnDisk"] and found[0].location.uri.endswith("closed.rdcd")
    finally:
        session.close()


def test_show_bytecode(lsp: Session) -> None:
    uri, _ = open_example(lsp, "bytecode")
    listing = lsp.request(types.WORKSPACE_EXECUTE_COMMAND, types.ExecuteCommandParams(
        command="rdcd.showBytecode", arguments=[uri]))
    assert isinstance(listing, str) and "discover_Axle" in listing
    broken = "file:///virtual/bytecode-broken.rdcd"
    lsp.open(broken, "role A { startup go() { self.nothing(); } }\ndeployment { A }\n")
    with pytest.raises(Exception, match="cannot compile"):
        lsp.request(types.WORKSPACE_EXECUTE_COMMAND, types.ExecuteCommandParams(
            command="rdcd.showBytecode", arguments=[broken]))
