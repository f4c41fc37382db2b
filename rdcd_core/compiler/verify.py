"""Checks every fragment with the VM's verifier (when ``vm.isa.verifier`` exists) and refuses
extension opcodes under --strict-isa."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.program import Fragment
from rdcd_core.source import Span


def verifier_errors(code: bytes, strict: bool = False) -> list[str]:
    try:
        from vm.isa import verifier
    except ImportError:
        return []
    check = getattr(verifier, "verify", None)
    if check is None:
        return []
    try:
        result = check(code, strict=strict)
    except Exception as error:  # the verifier raises on malformed code
        return [str(error)]
    if isinstance(result, (list, tuple)):
        return [str(r) for r in result]
    return []


def verify_fragments(fragments: list[Fragment], strict: bool) -> list[diag.Diagnostic]:
    found = []
    for fragment in fragments:
        for error in verifier_errors(fragment.code, strict):
            found.append(diag.make(codes.VERIFIER_REJECTED, fragment.span or Span(0, 0),
                                   f"fragment {fragment.name} rejected by the verifier: {error}"))
    return found
