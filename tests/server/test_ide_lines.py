"""IDE functions on texts whose lines end in \\r\\n or a lone \\r: fixes write the text's own line
break, a line comment ends at a lone \\r for completion as for the parser, folds and tokens use
the LSP's lines."""

from __future__ import annotations

import pytest

from rdcd_core.ide import actions, completion, folding
from rdcd_core.ide.analysis import analyze
from rdcd_core.ide.context import blank_comments
from rdcd_core.source import Span, count_line_breaks, normalize_newlines

MISSING = "abstract role W {\n  abstract constant speed;\n}\n\nrole R extends W { }\n\ndeployment { R }\n"


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_fixes_write_the_texts_line_break(newline: str) -> None:
    text = normalize_newlines(MISSING, newline)
    analysis = analyze(text)
    found = [a for a in actions.code_actions(analysis, Span(0, len(text))) if "missing" in a.fix.title]
    assert found
    for action in found:
        for edit in action.fix.edits:
            fixed = text[:edit.span.start] + edit.new_text + text[edit.span.end:]
            assert count_line_breaks(fixed) == fixed.count(newline)


def test_a_line_comment_ends_at_a_lone_cr_for_completion_too() -> None:
    text = "role A {\r  startup go() {\r    // note\r    self.\r  }\r}\rdeployment { A }\r"
    assert "self." in blank_comments(text)
    assert "note" not in blank_comments(text)
    offset = text.index("self.") + len("self.")
    _, items = completion.complete(text, offset, analyze(text).model)
    assert any(item.label == "sleep" for item in items)


def test_folds_span_lone_cr_lines() -> None:
    text = "role A {\r  startup go() {\r    self.sleep();\r  }\r}\rdeployment { A }\r"
    folds = folding.folding_ranges(analyze(text))
    assert [(f.start_line, f.end_line) for f in folds] == [(0, 4), (1, 3)]
