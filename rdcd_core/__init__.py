"""rdcd_core: the RDCD language — syntax, semantics, compiler, formatter, diagnostics, CLI."""

__version__ = "0.1.0"
