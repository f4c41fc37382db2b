"""The RDCD front end: grammar.lark, the LALR parser with error recovery, the AST."""

from rdcd_core.syntax.parser import ParseResult, parse

__all__ = ["ParseResult", "parse"]
