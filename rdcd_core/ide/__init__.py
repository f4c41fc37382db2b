"""IDE features as plain functions over the checked model (rust-analyzer style).

Every function takes an ``Analysis`` (one text and what the front end made of it) and offsets into
that text, and returns plain values with ``Span``s. ``server/`` maps them to LSP.
"""
