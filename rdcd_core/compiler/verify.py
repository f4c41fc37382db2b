"""Checks every fragment with the VM's verifier: first its form (an error there is a compiler bug,
E607), then the target's description (opcodes it runs, operand stack, instructions per run; E608)."""

from __future__ import annotations

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.program import Fragment
from rdcd_core.source import Span
from vm.isa.targets import Target
from vm.isa.verifier import verify


def verify_fragments(fragments: list[Fragment], target: Target) -> list[diag.Diagnostic]:
    found: list[diag.Diagnostic] = []
    verdicts: dict[bytes, tuple[list, str]] = {}  # a large program repeats fragments byte for byte
    for fragment in fragments:
        span = fragment.span or Span(0, 0)
        if fragment.code not in verdicts:
            verdicts[fragment.code] = _verdict(fragment.code, target)
        errors, code = verdicts[fragment.code]
        for error in errors:
            what = "rejected by the verifier" if code == codes.VERIFIER_REJECTED else \
                f"does not run on the {target.name} target"
            found.append(diag.make(code, span, f"fragment {fragment.name} {what}: {error}"))
    return found


def _verdict(blob: bytes, target: Target) -> tuple[list, str]:
    errors = verify(blob, max_stack=255)  # its form; the stack depth is the target's
    if errors:
        return errors, codes.VERIFIER_REJECTED
    return verify(blob, target=target), codes.TARGET_LIMIT
