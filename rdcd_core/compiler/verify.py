"""Checks every fragment with the VM's verifier, which also refuses extension opcodes under
--strict-isa."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.program import Fragment
from rdcd_core.source import Span
from vm.isa.verifier import verify


def verify_fragments(fragments: list[Fragment], strict: bool) -> list[diag.Diagnostic]:
    return [diag.make(codes.VERIFIER_REJECTED, fragment.span or Span(0, 0),
                      f"fragment {fragment.name} rejected by the verifier: {error}")
            for fragment in fragments for error in verify(fragment.code, strict=strict)]
