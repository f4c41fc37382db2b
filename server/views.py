"""Whole-document features: symbols, semantic tokens, folding ranges, inlay hints."""

from __future__ import annotations

import asyncio
from typing import TYPE_CHECKING

from lsprotocol import types

from rdcd_core.ide import folding, inlay, symbols, tokens
from server import workspace_files
from server.convert import Positions
from server.guard import guarded

if TYPE_CHECKING:
    from server.app import RdcdServer

SYMBOL_KINDS = {
    "role": types.SymbolKind.Class,
    "mixin": types.SymbolKind.Interface,
    "constant": types.SymbolKind.Constant,
    "state": types.SymbolKind.Variable,
    "method": types.SymbolKind.Method,
    "deployment": types.SymbolKind.Namespace,
}
LEGEND = types.SemanticTokensLegend(token_types=list(tokens.TOKEN_TYPES),
                                    token_modifiers=list(tokens.TOKEN_MODIFIERS))


def _document_symbol(symbol: symbols.Symbol, positions: Positions) -> types.DocumentSymbol:
    return types.DocumentSymbol(
        name=symbol.name, detail=symbol.detail, kind=SYMBOL_KINDS.get(symbol.kind, types.SymbolKind.Field),
        range=positions.range(symbol.span), selection_range=positions.range(symbol.selection),
        children=[_document_symbol(c, positions) for c in symbol.children] or None)


def encode_tokens(found: list[tokens.Token], positions: Positions) -> list[int]:
    """The LSP relative encoding; tokens spanning lines (block comments) are cut per line."""
    types_index = {name: i for i, name in enumerate(tokens.TOKEN_TYPES)}
    modifier_bits = {name: 1 << i for i, name in enumerate(tokens.TOKEN_MODIFIERS)}
    data: list[int] = []
    previous_line = previous_char = 0
    for token in found:
        bits = sum(modifier_bits[m] for m in token.modifiers)
        start, end = positions.position(token.span.start), positions.position(token.span.end)
        pieces = []
        if start.line == end.line:
            pieces.append((start.line, start.character, end.character - start.character))
        else:
            index = positions.index
            for line in range(start.line, end.line + 1):
                first = start.character if line == start.line else 0
                if line == end.line:
                    last = end.character
                else:
                    last = positions.position(index.offset(line, len(index.line_text(line)))).character
                pieces.append((line, first, last - first))
        for line, char, length in pieces:
            if length <= 0:
                continue
            delta_line = line - previous_line
            delta_char = char - previous_char if delta_line == 0 else char
            data += [delta_line, delta_char, length, types_index[token.type], bits]
            previous_line, previous_char = line, char
    return data


def register(server: RdcdServer) -> None:
    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    @guarded(list)
    async def on_document_symbol(ls: RdcdServer,
                                 params: types.DocumentSymbolParams) -> list[types.DocumentSymbol]:
        found = await ls.checked(params.text_document.uri)
        if found is None:
            return []
        document, analysis = found
        positions = ls.positions(document)
        return [_document_symbol(s, positions) for s in symbols.document_symbols(analysis)]

    @server.feature(types.WORKSPACE_SYMBOL)
    @guarded(list)
    async def on_workspace_symbol(ls: RdcdServer,
                                  params: types.WorkspaceSymbolParams) -> list[types.SymbolInformation]:
        # open documents: the newest finished analysis (symbols need only the syntax tree)
        documents = {}
        for uri, opened in list(ls.documents.open.items()):
            analysis = opened.analysis or opened.newest or await ls.analysis_of(opened)
            if analysis is not None:
                documents[uri] = analysis
        # the folders' other files: a bounded walk, in a thread so the loop goes on answering
        closed = await asyncio.get_running_loop().run_in_executor(
            None, workspace_files.closed_documents, ls, set(ls.documents.open))
        documents.update(closed)
        result = []
        for uri, symbol, container in symbols.workspace_symbols(documents, params.query):
            opened = ls.documents.get(uri)
            if opened is not None and documents[uri].text is opened.text:
                positions = ls.positions(opened)
            else:
                positions = Positions(documents[uri].line_index, ls.encoding)
            location = types.Location(uri=uri, range=positions.range(symbol.selection))
            result.append(types.SymbolInformation(
                name=symbol.name, kind=SYMBOL_KINDS.get(symbol.kind, types.SymbolKind.Field),
                location=location, container_name=container or None))
        return result

    @server.feature(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, LEGEND)
    @guarded(lambda: types.SemanticTokens(data=[]))
    async def on_semantic_tokens(ls: RdcdServer, params: types.SemanticTokensParams) -> types.SemanticTokens:
        found = await ls.checked(params.text_document.uri)
        if found is None:
            return types.SemanticTokens(data=[])
        document, analysis = found
        return types.SemanticTokens(data=encode_tokens(tokens.semantic_tokens(analysis),
                                                       ls.positions(document)))

    @server.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
    @guarded(list)
    async def on_folding(ls: RdcdServer, params: types.FoldingRangeParams) -> list[types.FoldingRange]:
        found = await ls.checked(params.text_document.uri)
        if found is None:
            return []
        kinds = {"comment": types.FoldingRangeKind.Comment, "region": types.FoldingRangeKind.Region}
        return [types.FoldingRange(start_line=f.start_line, end_line=f.end_line, kind=kinds[f.kind])
                for f in folding.folding_ranges(found[1])]

    @server.feature(types.TEXT_DOCUMENT_INLAY_HINT)
    @guarded(list)
    async def on_inlay_hint(ls: RdcdServer, params: types.InlayHintParams) -> list[types.InlayHint]:
        if not ls.settings.fragment_size_hints:
            return []
        found = await ls.checked(params.text_document.uri)
        if found is None:
            return []
        document, analysis = found
        positions = ls.positions(document)
        span = positions.span(params.range)
        return [types.InlayHint(position=positions.position(h.offset), label=h.label, tooltip=h.tooltip,
                                padding_left=True)
                for h in inlay.fragment_hints(analysis, span.start, span.end)]
