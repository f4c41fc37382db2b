"""What a sequence needs of the DCD-VM, said at the line before it runs (docs/reconfiguration.md
"Limits"): program slots for the fragments the program with its sequences compiles to (E805) — a
module keeps every fragment that reaches it while the program is being spread, so the entry
refuses the fragment after the last slot. (E806, the progress past a signed byte, is gone: the
progress counts steps, at most 60, and a rollback's at most 2 * 60 + 1.)
(A role invariant on the progress, `S == N;`, once E807, now fits: state-dependent discovery is
split over fragments, docs/language.md "Fragments that fit".)"""

from __future__ import annotations

from typing import Any

from rdcd_core import diagnostics as diag
from rdcd_core.sequences import codes
from rdcd_core.syntax import ast


def slot_limit(model: Any, fragments: list[Any], slots: int) -> list[diag.Diagnostic]:
    """E805 when a program with sequences compiles to more fragments than ``slots``: at the
    code of the first step with no slot, else the last step's, else at the sequence's name."""
    sequences = model.program.sequences
    if not sequences or len(fragments) <= slots:
        return []
    over = fragments[slots:]
    steps = [s for q in sequences for item in q.items
             for s in ((item,) if isinstance(item, ast.SeqStep) else item.steps)]
    in_steps = [f.span for f in fragments if f.span is not None and
                any(s.span.start <= f.span.start < s.span.end for s in steps)]
    over_steps = [f.span for f in over if f.span in in_steps]
    # the first step's code with no slot; else the last step's code (where the program got too big)
    span = (over_steps or in_steps[-1:] or [sequences[0].name.span])[0]
    names = ", ".join(f.name for f in over)
    return [diag.make(codes.TOO_MANY_FRAGMENTS, span,
                      f"with its sequences the program compiles to {len(fragments)} fragments and a "
                      f"module has {slots} program slots: the entry module would refuse {names} "
                      "and the sequence would stop there; use fewer steps per role (a step alone "
                      "takes half a behaviour, a step of a parallel block after its first two, one with a "
                      "condition one), or fewer roles")]
