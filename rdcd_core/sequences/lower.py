"""Sequences compiled as ordinary RDCD code (docs/reconfiguration.md "How it runs").

Each sequence ``S`` becomes a module state ``S`` (its progress: the number of steps done), published
to the neighbours, and behaviours in every deployed role:

- ``S_relay``: ``S := max(S, max(neighbours.S));`` — every module takes the furthest progress it
  hears of, so progress spreads through the whole robot; a lost packet is sent again (published
  values are acknowledged) and only delays it;
- for the steps of role R, behaviours ``S_R_i`` with up to two steps each:
  ``if (S == k && condition) { if (self.connect(c)) { S := k + 1; } }`` — the module holding R acts
  when the progress it has heard says step k is next, and only it moves the progress on. A failed
  action leaves the progress at k and is tried again on the next run of the behaviour.

Steps are numbered in order; the steps of a parallel block are numbered in the order written
(they run one after the other: the checker has made sure they touch different modules, so the
order does not change the result). ``reverse``: the undo of each step in reverse order.

The generated members carry the span of their step (or the sequence's), so a diagnostic of the
compiler points at the step.
"""

from __future__ import annotations

from dataclasses import fields, is_dataclass, replace
from typing import Any

from rdcd_core.formatter import expr
from rdcd_core.sequences.check import INVERSE, STEP_ACTIONS, stages
from rdcd_core.source import Span
from rdcd_core.syntax import ast

STEPS_PER_BEHAVIOUR = 2  # two steps' code fits a 43-byte fragment with room for a condition


def step_code(sequence: str, k: int, step: ast.SeqStep, reverse: bool = False, *,
              at: int | None = None, then: int | None = None, failed: int | None = None) -> str | None:
    """The statement of step number ``k`` (0-based): it acts when the progress is ``at`` (default
    k), then sets it to ``then`` (default k + 1), or to ``failed`` when the action fails (default:
    unchanged, tried again). None for a step the checker rejects."""
    action = step.action.text
    if action not in STEP_ACTIONS or len(step.args) != 1 or isinstance(step.args[0], ast.Block):
        return None
    if reverse:
        action = INVERSE[action]
    at = k if at is None else at
    then = k + 1 if then is None else then
    guard = f"{sequence} == {at}"
    if step.condition is not None:
        guard += f" && ({expr(step.condition)})"
    arg = expr(step.args[0])
    if action == "waitUntil":
        return f"if ({guard} && ({arg})) {{ {sequence} := {then}; }}"
    if action == "turnQuarters" and reverse:
        arg = f"0 - ({arg})"
    otherwise = f" else {{ {sequence} := {failed}; }}" if failed is not None else ""
    return f"if ({guard}) {{ if (self.{action}({arg})) {{ {sequence} := {then}; }}{otherwise} }}"


def ordered_steps(sequence: ast.Sequence, reverse: bool = False) -> list[ast.SeqStep]:
    steps = [step for stage in stages(sequence) for step in stage]
    return list(reversed(steps)) if reverse else steps


def members_for(sequence: ast.Sequence, deployed: list[str], parents: dict[str, str | None],
                reverse: bool = False) -> dict[str, list[tuple[str, Span]]]:
    """Per deployed role, the generated members' text with the span they stand for."""
    name = sequence.name.text
    out: dict[str, list[tuple[str, Span]]] = {
        role: [(f"behavior {name}_relay() {{ {name} := max({name}, max(neighbours.{name})); }}",
                sequence.header_span)] for role in deployed}
    by_role: dict[str, list[tuple[str, Span]]] = {}
    steps = ordered_steps(sequence, reverse)
    n = len(steps)
    rollback = sequence.modifier is not None and sequence.modifier.text == "rollback"
    for k, step in enumerate(steps):
        # rollback: progress 2n - j means "undo step j next"; a failure at step k undoes k - 1 first,
        # and 2n + 1 is "rolled back" — the progress still only grows, so max() still spreads it
        code = step_code(name, k, step, reverse, failed=2 * n - k + 1 if rollback else None)
        if code is not None and step.role.text in out:
            by_role.setdefault(step.role.text, []).append((code, step.span))
        if rollback and step.action.text != "waitUntil":
            undo = step_code(name, k, step, not reverse, at=2 * n - k, then=2 * n - k + 1)
            if undo is not None and step.role.text in out:
                by_role.setdefault(step.role.text, []).append((undo, step.span))
    for role, codes in by_role.items():
        per = 1 if rollback else STEPS_PER_BEHAVIOUR  # a step with its failure branch fills one
        chunks: list[list[tuple[str, Span]]] = [[]]
        for code, span in codes:  # a step with a condition takes a behaviour alone
            if len(chunks[-1]) == per or (chunks[-1] and "&& (" in code + chunks[-1][0][0]):
                chunks.append([])
            chunks[-1].append((code, span))
        for i, chunk in enumerate(chunks):
            body = " ".join(code for code, _ in chunk)
            out[role].append((f"behavior {name}_{role}_{i}() {{ {body} }}", chunk[0][1]))
    return out


def lower(program: ast.Program, reverse: str | None = None) -> ast.Program:
    """``program`` with its sequences as state and behaviours (``reverse``: the name of a sequence
    to run backwards instead)."""
    from rdcd_core.syntax.parser import parse

    if not program.sequences or program.deployment is None:
        return program
    deployed = [n.text for n in program.deployment.roles]
    decls = {role.name.text: role for role in program.roles}
    parents = {n: (d.extends.text if d.extends else None) for n, d in decls.items()}
    extra: dict[str, list[ast.Member]] = {}
    states = list(program.states)
    seen: set[str] = set()
    for sequence in program.sequences:
        name = sequence.name.text
        if name in seen:
            continue
        seen.add(name)
        if not any(s.name.text == name for s in program.states):
            states.append(_respan(_state(name), sequence.name.span))
        generated = members_for(sequence, [r for r in deployed if r in decls], parents,
                                reverse == name)
        for role, items in generated.items():
            for text, span in items:
                parsed = parse(f"role G {{ {text} }} deployment {{ G }}")
                if parsed.diagnostics or not parsed.program.roles:
                    continue  # an argument the checker reports (E803): nothing to compile
                extra.setdefault(role, []).extend(_respan(m, span) for m in parsed.program.roles[0].members)
    roles = tuple(replace(role, members=role.members + tuple(extra.get(role.name.text, ())))
                  for role in program.roles)
    return replace(program, roles=roles, states=tuple(states))


def with_progress_states(program: ast.Program) -> ast.Program:
    """``program`` with the progress state of each sequence declared (so that roles can read it,
    e.g. ``S == 3;`` for a role of the shape after it), unless a state of that name exists (E801)."""
    if not program.sequences:
        return program
    names = {s.name.text for s in program.states}
    extra = []
    for sequence in program.sequences:
        if sequence.name.text not in names:
            names.add(sequence.name.text)
            extra.append(_respan(_state(sequence.name.text), sequence.name.span))
    return replace(program, states=program.states + tuple(extra)) if extra else program


def _state(name: str) -> ast.StateDecl:
    from rdcd_core.syntax.parser import parse

    return parse(f"state {name} := 0; deployment {{ }}").program.states[0]


def _respan(node: Any, span: Span) -> Any:
    if isinstance(node, Span):
        return span
    if isinstance(node, tuple):
        return tuple(_respan(n, span) for n in node)
    if is_dataclass(node) and not isinstance(node, type):
        return replace(node, **{f.name: _respan(getattr(node, f.name), span) for f in fields(node)
                                if f.init})
    return node


def lowered_model(model: Any, reverse: str | None = None) -> Any:
    """The model of the program with its sequences lowered (analysed again)."""
    from rdcd_core.semantics import analyze

    return analyze(lower(model.program, reverse))
