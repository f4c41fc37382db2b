"""Random sequences of incremental edits: the server stays up and its final diagnostics equal a
fresh ``check_text`` of the final text."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lsprotocol import types

from rdcd_core.frontend import check_text
from tests.server.conftest import EXAMPLES, Session

SEED = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()
SNIPPETS = ["", ";", "}", "{", "self.", "role X { }", "constant k := 3;", "(", ")", "é", "😀", "\n",
            "deployment { Axle }", "Wheel", "if (", "//", "/*", "*/", " ", "abstract ", "-1"]


@st.composite
def edit(draw: st.DrawFn) -> tuple[float, float, str]:
    return draw(st.floats(0, 1)), draw(st.floats(0, 0.2)), draw(st.sampled_from(SNIPPETS))


def apply(text: str, start_fraction: float, length_fraction: float, insert: str) -> tuple[str, int, int]:
    start = int(start_fraction * len(text))
    end = min(len(text), start + int(length_fraction * 40))
    return text[:start] + insert + text[end:], start, end


def lsp_position(text: str, offset: int) -> types.Position:
    line = text.count("\n", 0, offset)
    line_start = text.rfind("\n", 0, offset) + 1
    units = len(text[line_start:offset].encode("utf-16-le")) // 2
    return types.Position(line=line, character=units)


counter = [0]


@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.lists(edit(), min_size=1, max_size=12))
def test_random_edits_end_in_fresh_diagnostics(lsp: Session, edits: list[tuple[float, float, str]]) -> None:
    counter[0] += 1
    uri = f"file:///virtual/property-{counter[0]}.rdcd"
    text = SEED
    lsp.open(uri, text)
    for start_fraction, length_fraction, insert in edits:
        new_text, start, end = apply(text, start_fraction, length_fraction, insert)
        change = types.TextDocumentContentChangePartial(
            range=types.Range(start=lsp_position(text, start), end=lsp_position(text, end)), text=insert)
        lsp.change(uri, [change], wait=False)
        text = new_text
    published = lsp.diagnostics(uri, lsp.versions[uri])
    versions = [p.version for p in lsp.client.published[uri]]  # type: ignore[attr-defined]
    assert versions == sorted(versions), "an older result was published over a newer one"
    expected = check_text(text).diagnostics
    assert [(d.code, d.message) for d in published] == [(d.code, d.message) for d in expected]
    lines = text.split("\n")
    for got, want in zip(published, expected, strict=True):
        line = text.count("\n", 0, want.span.start)
        column = want.span.start - (text.rfind("\n", 0, want.span.start) + 1)
        units = len(lines[line][:column].encode("utf-16-le")) // 2
        assert (got.range.start.line, got.range.start.character) == (line, units)
    lsp.close_document(uri)
