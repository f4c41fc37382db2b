"""The progress values of a sequence (docs/reconfiguration.md "How it runs"): the number of steps
done. Each stage takes a range of them, one value a step: the steps of a parallel block act at
once and are counted in order (lower.py), so the progress when the sequence is done is its number
of steps. With ``rollback`` the steps of a block run one after the other (the undo counts the
steps done), and the values past the number of steps n say what to undo next (``undo_value``)."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.source import Span
from rdcd_core.syntax import ast


@dataclass(frozen=True)
class Stage:
    """One stage of a sequence as it runs: its steps, its first progress value and how many
    values it takes (one a step); ``block``: 1.. for a parallel block run at once, 0 otherwise;
    ``span``: the block's (or the step's)."""

    steps: tuple[ast.SeqStep, ...]
    base: int
    width: int
    block: int
    span: Span


def is_rollback(sequence: ast.Sequence) -> bool:
    return sequence.modifier is not None and sequence.modifier.text == "rollback"


def progress_plan(sequence: ast.Sequence, reverse: bool = False) -> list[Stage]:
    """The stages in the order they run, with their progress values."""
    items: list[tuple[tuple[ast.SeqStep, ...], Span]] = []
    for item in sequence.items:
        if isinstance(item, ast.SeqStep):
            items.append(((item,), item.span))
        elif item.steps and is_rollback(sequence):  # one after the other (the undo counts steps)
            items.extend(((step,), step.span) for step in item.steps)
        elif item.steps:
            items.append((tuple(item.steps), item.span))
    if reverse:
        items = [(tuple(reversed(steps)), span) for steps, span in reversed(items)]
    out: list[Stage] = []
    base, blocks = 0, 0
    for steps, span in items:
        block = 0
        if len(steps) > 1:
            blocks += 1
            block = blocks
        width = len(steps)
        out.append(Stage(steps, base, width, block, span))
        base += width
    return out


def done_value(sequence: ast.Sequence) -> int:
    """The progress when every step is done: the number of steps."""
    plan = progress_plan(sequence)
    return plan[-1].base + plan[-1].width if plan else 0


def steps_done(sequence: ast.Sequence, value: int) -> int:
    """How many steps a progress value says are done (forward progress only): the value itself,
    at most the number of steps."""
    return max(0, min(value, done_value(sequence)))


def undo_value(n: int, j: int) -> int:
    """With ``rollback`` and n steps: the progress at which the undo of step j (0-based) runs,
    2n - 1 - j, so that a failure at step k sets ``undo_value(n, k - 1)`` ("undo step k - 1
    next", 2n - k) and each undo sets the next one's value, the progress still only growing.
    The last step's undo (which would be n, "done") is never needed: a failure after it is
    impossible. ``undo_value(n, -1)`` is ``rolled_back_value(n)``."""
    return 2 * n - 1 - j


def rolled_back_value(n: int) -> int:
    """With ``rollback`` and n steps: the progress that says every step done has been undone."""
    return undo_value(n, -1)
