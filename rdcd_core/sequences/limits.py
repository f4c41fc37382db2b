"""What a sequence needs of the DCD-VM, said at the line before it runs (docs/reconfiguration.md
"Limits"): progress values within a state byte (E806), program slots for the fragments the
program with its sequences compiles to (E805) — a module keeps every fragment that reaches it
while the program is being spread, so the entry refuses the fragment after the last slot.
(A role invariant on the progress, `S == N;`, once E807, now fits: state-dependent discovery is
split over fragments, docs/language.md "Fragments that fit".)"""

from __future__ import annotations

from typing import Any

from rdcd_core import diagnostics as diag
from rdcd_core.sequences import codes
from rdcd_core.sequences.progress import MAX_PROGRESS, progress_plan
from rdcd_core.syntax import ast


def progress_limit(sequence: ast.Sequence) -> list[diag.Diagnostic]:
    """E806 at the first stage whose progress values go past a signed byte."""
    for stage in progress_plan(sequence):
        if stage.base + stage.width > MAX_PROGRESS:
            what = (f"this parallel block of {len(stage.steps)} steps takes {stage.width} progress "
                    "values (2^m - 1: a bit for each step)" if stage.block else "this step")
            return [diag.make(codes.PROGRESS_RANGE, stage.span,
                              f"{what} and ends at progress {stage.base + stage.width}; the progress "
                              f"of sequence '{sequence.name.text}' is a signed byte (at most "
                              f"{MAX_PROGRESS}): split the block into smaller blocks one after the "
                              "other")]
    return []


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
                      "takes half a behaviour, a step of a parallel block two, one with a "
                      "condition one), or fewer roles")]
