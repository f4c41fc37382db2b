"""The progress values of a sequence (docs/reconfiguration.md "How it runs"): each stage takes a
range of them — a step alone one value, a parallel block of m steps run at once 2^m - 1, read as
the bitmask of its steps done — and the progress when the sequence is done is the sum. With
``rollback`` the steps of a block run one after the other (the undo counts the steps done)."""

from __future__ import annotations

from dataclasses import dataclass

from rdcd_core.source import Span
from rdcd_core.syntax import ast

MAX_PROGRESS = 127  # the progress is a signed byte


@dataclass(frozen=True)
class Stage:
    """One stage of a sequence as it runs: its steps, its first progress value and how many
    values it takes (1 for a step alone, 2^m - 1 for m steps run at once); ``block``: 1.. for a
    parallel block run at once, 0 otherwise; ``span``: the block's (or the step's)."""

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
        width = (1 << len(steps)) - 1 if len(steps) < 16 else 1 << 16
        out.append(Stage(steps, base, width, block, span))
        base += width
    return out


def done_value(sequence: ast.Sequence) -> int:
    """The progress when every step is done (the number of steps when no block runs at once)."""
    plan = progress_plan(sequence)
    return plan[-1].base + plan[-1].width if plan else 0


def steps_done(sequence: ast.Sequence, value: int, reverse: bool = False) -> int:
    """How many steps a progress value says are done (forward progress only)."""
    done = 0
    for stage in progress_plan(sequence, reverse):
        if value >= stage.base + stage.width:
            done += len(stage.steps)
        elif value > stage.base and stage.block:
            done += bin(value - stage.base).count("1")
    return done
