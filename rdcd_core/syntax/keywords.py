"""The keywords of RDCD (language.md §1): the parser and the editor grammar read this list."""

KEYWORDS: tuple[str, ...] = (
    "abstract", "role", "extends", "modifies", "constant", "startup", "behavior", "command",
    "if", "else", "deployment", "self",
)
