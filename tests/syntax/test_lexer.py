"""The lexer: derived from grammar.lark, agrees with keywords.py and docs/language.md"""

from __future__ import annotations

from rdcd_core.syntax import parse
from rdcd_core.syntax.keywords import KEYWORDS
from rdcd_core.syntax.tables import tables


def lex(text: str) -> list[tuple[str, str]]:
    return [(tok.type, tok.value) for tok in tables().lexer.lex(text).tokens]


def test_keywords_agree_with_keywords_py() -> None:
    assert set(tables().lexer.keywords) == set(KEYWORDS)


def test_punctuation_and_operators_of_the_spec() -> None:
    spec = "{ } ( ) , ; . := || && == != < > <= >= + - * / % !".split()
    assert set(tables().lexer.literals) == set(spec)


def test_longest_match_and_keyword_prefixes() -> None:
    assert lex("a<=b:=c!=!d") == [("NAME", "a"), ("LE", "<="), ("NAME", "b"), ("ASSIGN", ":="),
                                  ("NAME", "c"), ("NE", "!="), ("BANG", "!"), ("NAME", "d")]
    assert lex("roles role _role2 007") == [("NAME", "roles"), ("ROLE", "role"), ("NAME", "_role2"),
                                           ("INT", "007")]


def test_token_positions() -> None:
    tokens = tables().lexer.lex("  ab /* c */ 12\n;").tokens
    assert [(t.start, t.end) for t in tokens] == [(2, 4), (13, 15), (16, 17)]


def test_bad_characters_are_merged_and_dropped() -> None:
    result = tables().lexer.lex("a @#$ b é")
    assert [t.value for t in result.tokens] == ["a", "b"]
    found = [(d.code, d.span.start, d.span.end) for d in result.diagnostics]
    assert found == [("E001", 2, 5), ("E001", 8, 9)]


def test_unterminated_comment_runs_to_the_end() -> None:
    text = "role A { } /* open\ndeployment { A }"
    result = parse(text)
    assert [d.code for d in result.diagnostics] == ["E002"]
    assert result.program.comments[-1].text == text[11:]
    assert result.program.deployment is None


def test_crlf_line_ends_and_byte_order_mark() -> None:
    result = parse("\ufeffrole A { // note\r\n  x;\r\n}\r\ndeployment { A }\r\n")
    assert result.diagnostics == []
    assert [c.text for c in result.program.comments] == ["// note"]
