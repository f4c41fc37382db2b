"""Adversarial input for the IDE features on state: random edits of a program with state and
parameters never make a feature raise, and what a rename returns keeps the program's meaning;
a program with 1,000 states is answered in full."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.ide import actions, completion, hover, navigation, rename, signature, symbols, tokens
from rdcd_core.ide.analysis import analyze
from rdcd_core.source import Span

PROGRAM = (Path(__file__).parent / "data" / "state_names.rdcd").read_text()
PIECES = ["", ";", "}", "{", "(", ")", ":=", "state ", "state s := 1;", "neighbours.", "children.",
          "neighbours(DOWN).", "min(", "count(", "sum(children.hops)", "hops", "seen", "speed", ",",
          "-128", "127", "Node.turn(", "self.helper(", "é", "\n", "//", "/*", " ", "x := ;"]


@st.composite
def edits(draw: st.DrawFn) -> str:
    text = PROGRAM
    for _ in range(draw(st.integers(1, 6))):
        start = draw(st.integers(0, len(text)))
        end = min(len(text), start + draw(st.integers(0, 12)))
        text = text[:start] + draw(st.sampled_from(PIECES)) + text[end:]
    return text


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(edits(), st.lists(st.floats(0, 1), min_size=1, max_size=8))
def test_features_never_raise_on_edited_state_programs(text: str, fractions: list[float]) -> None:
    analysis = analyze(text)
    tokens.semantic_tokens(analysis)
    symbols.document_symbols(analysis)
    actions.code_actions(analysis, Span(0, len(text)))
    for fraction in fractions:
        offset = int(fraction * len(text))
        hover.hover(analysis, offset)
        navigation.definition(analysis, offset)
        navigation.highlights(analysis, offset)
        completion.complete(text, offset, analysis.model)
        signature.signature_help(text, offset, analysis.model)
        if rename.prepare_rename(analysis, offset) is None:
            continue
        try:
            edits_ = rename.rename(analysis, offset, "renamed_name")
        except rename.RenameError:
            continue
        renamed = text
        for edit in sorted(edits_, key=lambda e: e.span.start, reverse=True):
            renamed = renamed[:edit.span.start] + edit.new_text + renamed[edit.span.end:]
        # a fresh name clashes with nothing: the renamed program has the same diagnostics
        after = sorted(d.code for d in analyze(renamed).diagnostics)
        assert after == sorted(d.code for d in analysis.diagnostics)


def test_a_thousand_states() -> None:
    declarations = "".join(f"state s{k} := {k % 128};\n" for k in range(1000))
    text = declarations + "role A {\n  behavior b() {\n    s0 := s999 + 1;\n  }\n}\ndeployment { A }\n"
    analysis = analyze(text)
    assert "E720" in [d.code for d in analysis.diagnostics]  # more than the VM holds: reported
    found = hover.hover(analysis, text.index("s999 + 1") + 1)
    assert found is not None and "module state** `s999` := 103" in found.markdown
    assert len(symbols.document_symbols(analysis)) == 1002
    edited = text.replace("s999 + 1", "neighbours.", 1)
    offset = edited.index("neighbours.") + len("neighbours.")
    assert len(completion.complete(edited, offset, analysis.model)[1]) == 1000
    try:
        rename.rename(analysis, text.index("s0 :=") + 1, "s500")
    except rename.RenameError as error:
        assert "s500" in str(error)
    else:
        raise AssertionError("a clash with one of 1,000 states must be refused")
    assert len(rename.rename(analysis, text.index("s0 :=") + 1, "first")) == 2
