"""Language features that answer a position: hover, navigation, rename, completion, signature help,
code actions and formatting. Each maps an ``rdcd_core.ide`` function to LSP."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types

from rdcd_core import formatter
from rdcd_core.diagnostics import TextEdit
from rdcd_core.ide import actions, completion, hover, navigation, rename, signature
from rdcd_core.source import Span
from server.convert import Positions
from server.guard import RequestFailed, guarded
from server.lsp_diagnostics import to_lsp_diagnostic

if TYPE_CHECKING:
    from server.app import RdcdServer

COMPLETION_KINDS = {
    "role": types.CompletionItemKind.Class,
    "mixin": types.CompletionItemKind.Interface,
    "constant": types.CompletionItemKind.Constant,
    "state": types.CompletionItemKind.Variable,
    "parameter": types.CompletionItemKind.Variable,
    "method": types.CompletionItemKind.Method,
    "command": types.CompletionItemKind.Event,
    "primitive": types.CompletionItemKind.Function,
    "function": types.CompletionItemKind.Function,
    "predefined": types.CompletionItemKind.EnumMember,
    "keyword": types.CompletionItemKind.Keyword,
}


def _edits(positions: Positions, edits: list[TextEdit]) -> list[types.TextEdit]:
    return [types.TextEdit(range=positions.range(e.span), new_text=e.new_text) for e in edits]


def _locate(ls: RdcdServer, params):  # type: ignore[no-untyped-def]
    """(document, positions, offset) for a position request, or None for an unknown document."""
    document = ls.document(params.text_document.uri)
    if document is None:
        return None
    positions = ls.positions(document)
    return document, positions, positions.offset(params.position)


async def _exact(ls: RdcdServer, params):  # type: ignore[no-untyped-def]
    """(document, positions, offset, analysis) for a request whose answer must match the text it
    was asked on (locations, edits): waits for that text's check without holding up the loop;
    None for an unknown document, or when the text changed meanwhile (the client asks again)."""
    found = await ls.checked(params.text_document.uri)
    if found is None:
        return None
    document, analysis = found
    positions = ls.positions(document)
    return document, positions, positions.offset(params.position), analysis


def register(server: RdcdServer) -> None:
    @server.feature(types.TEXT_DOCUMENT_HOVER)
    @guarded()
    def on_hover(ls: RdcdServer, params: types.HoverParams) -> types.Hover | None:
        """Never waits for a check: answers from the newest finished analysis, outside the part
        of the text edited since (a long check must not make hovering hang)."""
        located = _locate(ls, params)
        if located is None:
            return None
        document, positions, offset = located
        found = document.stale()
        if found is None:
            return None
        analysis, shift = found
        old = shift.to_old(offset)
        result = hover.hover(analysis, old) if old is not None else None
        span = shift.to_new(result.span) if result is not None else None
        if result is None or span is None:
            return None
        content = types.MarkupContent(kind=types.MarkupKind.Markdown, value=result.markdown)
        return types.Hover(contents=content, range=positions.range(span))

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    @guarded(list)
    async def on_definition(ls: RdcdServer, params: types.DefinitionParams) -> list[types.Location]:
        located = await _exact(ls, params)
        if located is None:
            return []
        document, positions, offset, analysis = located
        return [types.Location(uri=document.uri, range=positions.range(span))
                for span in navigation.definition(analysis, offset)]

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    @guarded(list)
    async def on_references(ls: RdcdServer, params: types.ReferenceParams) -> list[types.Location]:
        located = await _exact(ls, params)
        if located is None:
            return []
        document, positions, offset, analysis = located
        spans = navigation.references(analysis, offset, params.context.include_declaration)
        return [types.Location(uri=document.uri, range=positions.range(span)) for span in spans]

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
    @guarded(list)
    async def on_highlight(ls: RdcdServer,
                           params: types.DocumentHighlightParams) -> list[types.DocumentHighlight]:
        located = await _exact(ls, params)
        if located is None:
            return []
        _, positions, offset, analysis = located
        kinds = {True: types.DocumentHighlightKind.Write, False: types.DocumentHighlightKind.Read}
        return [types.DocumentHighlight(range=positions.range(span), kind=kinds[is_definition])
                for span, is_definition in navigation.highlights(analysis, offset)]

    @server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    @guarded()
    async def on_prepare_rename(ls: RdcdServer, params: types.PrepareRenameParams):  # type: ignore[no-untyped-def]
        located = await _exact(ls, params)
        if located is None:
            return None
        document, positions, offset, analysis = located
        span = rename.prepare_rename(analysis, offset)
        if span is None:
            return None
        text = document.text[span.start:span.end]
        return types.PrepareRenamePlaceholder(range=positions.range(span), placeholder=text)

    @server.feature(types.TEXT_DOCUMENT_RENAME, types.RenameOptions(prepare_provider=True))
    @guarded()
    async def on_rename(ls: RdcdServer, params: types.RenameParams) -> types.WorkspaceEdit | None:
        located = await _exact(ls, params)
        if located is None:
            return None
        document, positions, offset, analysis = located
        try:
            edits = rename.rename(analysis, offset, params.new_name)
        except rename.RenameError as error:
            raise RequestFailed(str(error)) from None
        return types.WorkspaceEdit(changes={document.uri: _edits(positions, edits)})

    register_editing(server)


def register_editing(server: RdcdServer) -> None:
    @server.feature(types.TEXT_DOCUMENT_COMPLETION,
                    types.CompletionOptions(trigger_characters=[".", "(", ",", " "]))
    @guarded()
    def on_completion(ls: RdcdServer, params: types.CompletionParams) -> types.CompletionList | None:
        located = _locate(ls, params)
        if located is None:
            return None
        document, positions, offset = located
        found = document.model_for_completion()  # never waits for a check
        model = found.model if found is not None else None
        start, items = completion.complete(document.text, offset, model)
        replace = positions.range(Span(start, offset))
        return types.CompletionList(is_incomplete=False, items=[_item(i, replace) for i in items])

    @server.feature(types.TEXT_DOCUMENT_SIGNATURE_HELP,
                    types.SignatureHelpOptions(trigger_characters=["(", ","], retrigger_characters=[","]))
    @guarded()
    def on_signature_help(ls: RdcdServer, params: types.SignatureHelpParams) -> types.SignatureHelp | None:
        located = _locate(ls, params)
        if located is None:
            return None
        document, _, offset = located
        found = document.model_for_completion()  # never waits for a check
        info = signature.signature_help(document.text, offset, found.model if found is not None else None)
        if info is None:
            return None
        parameters = [types.ParameterInformation(label=(a, b)) for a, b in info.parameters]
        sig = types.SignatureInformation(label=info.label, documentation=info.doc, parameters=parameters,
                                         active_parameter=info.active_parameter)
        return types.SignatureHelp(signatures=[sig], active_signature=0,
                                   active_parameter=info.active_parameter)

    @server.feature(types.TEXT_DOCUMENT_CODE_ACTION,
                    types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]))
    @guarded(list)
    async def on_code_action(ls: RdcdServer, params: types.CodeActionParams) -> list[types.CodeAction]:
        document = ls.document(params.text_document.uri)
        if document is None:
            return []
        text = document.text
        analysis = await ls.analysis_of(document)
        if analysis is None or document.text is not text:
            return []
        positions = ls.positions(document)
        result = []
        for action in actions.code_actions(analysis, positions.span(params.range)):
            edit = types.WorkspaceEdit(changes={document.uri: _edits(positions, list(action.fix.edits))})
            result.append(types.CodeAction(
                title=action.title, kind=types.CodeActionKind.QuickFix, edit=edit,
                diagnostics=[to_lsp_diagnostic(action.diagnostic, positions, document.uri)],
                is_preferred=action.preferred or None))
        return result

    @server.feature(types.TEXT_DOCUMENT_FORMATTING)
    @guarded(list)
    def on_formatting(ls: RdcdServer, params: types.DocumentFormattingParams) -> list[types.TextEdit]:
        document = ls.document(params.text_document.uri)
        if document is None:
            return []
        edits = formatter.format_edits(document.text)
        return _edits(ls.positions(document), edits or [])

    @server.feature(types.TEXT_DOCUMENT_RANGE_FORMATTING)
    @guarded(list)
    def on_range_formatting(ls: RdcdServer,
                            params: types.DocumentRangeFormattingParams) -> list[types.TextEdit]:
        document = ls.document(params.text_document.uri)
        if document is None:
            return []
        positions = ls.positions(document)
        edits = formatter.format_range(document.text, positions.span(params.range))
        return _edits(positions, edits or [])


def _item(item: completion.CompletionItem, replace: types.Range) -> types.CompletionItem:
    snippet = item.insert_text is not None and "$" in item.insert_text
    new_text = item.insert_text or item.label
    return types.CompletionItem(
        label=item.label,
        kind=COMPLETION_KINDS.get(item.kind, types.CompletionItemKind.Text),
        detail=item.detail or None,
        documentation=item.documentation or None,
        insert_text_format=types.InsertTextFormat.Snippet if snippet else types.InsertTextFormat.PlainText,
        text_edit=types.TextEdit(range=replace, new_text=new_text),
    )
