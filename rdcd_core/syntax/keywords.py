"""The keywords of RDCD (docs/language.md), for the editor features and the TextMate grammar test.

The lexer takes its keywords from grammar.lark; tests/syntax/test_lexer.py checks they agree."""

KEYWORDS: tuple[str, ...] = (
    "abstract", "role", "extends", "modifies", "constant", "startup", "behavior", "command",
    "if", "else", "deployment", "self", "state", "travelling", "neighbours", "children",
    "sequence", "parallel",
)
