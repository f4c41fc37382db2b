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

The progress is always the number of steps done (``progress_plan``). The steps of a parallel
block of m steps starting at k *act* at once and are *counted* in order: step j acts once as soon
as the progress reaches k (its module remembers, in a local state ``S_par``, the value the step counts
to) and counts it, k + j -> k + j + 1, once the progress says the steps before it are counted
(``parallel_code``). A block therefore takes as long as its slowest action, and its values mean
what a step's do. With ``rollback`` the steps of a block run one after the other (the undo of a
failed step needs the steps done before it). ``reverse``: the undo of each step in reverse order
(a parallel block stays parallel).

The generated members carry the span of their step (or the sequence's), so a diagnostic of the
compiler points at the step.
"""

from __future__ import annotations

import re
from dataclasses import fields, is_dataclass, replace
from typing import Any

from rdcd_core.formatter import expr
from rdcd_core.sequences.check import INVERSE, STEP_ACTIONS, stages
from rdcd_core.sequences.compact import ahead_steps, applies, count_order, role_table
from rdcd_core.sequences.progress import Stage, is_rollback, progress_plan, undo_value
from rdcd_core.source import Span
from rdcd_core.syntax import ast

STEPS_PER_BEHAVIOUR = 2  # two steps' code fits a 43-byte fragment with room for a condition


def parallel_code(sequence: str, stage: Stage, j: int, step: ast.SeqStep,
                  reverse: bool = False) -> tuple[str, str] | None:
    """Step j (1..m-1) of block ``stage``, which acts at once with the block's other steps and is
    counted in order, as two behaviours (one does not fit a fragment). With k the block's first
    progress value, the step is counted at k + j (step 0 is an ordinary step at k):

    - act once, as soon as the block has begun: ``if (S >= k && S_par < v)
      { if (self.disconnect(c)) { S_par := v; } }`` with v = k + j + 1 — the module remembers
      the value the step counts to; a module acts in one step of a block (E816) and earlier steps
      count to less, so ``S_par < v`` means "not done yet" (and the progress cannot pass k + j
      before it is done: only this module counts to v);
    - count it in its turn: ``if (S == k + j && S_par == v) { S := v; }`` — v is this step's
      alone, so only the module that did it counts it, once the steps before it are counted.

    The progress still only grows and max() still spreads it: a lost packet delays a count, never
    loses one, and the block is over when its last step is counted, each of its actions done."""
    if j == 0 or step_code(sequence, 0, step, reverse, at=0, then=0) is None:
        return None
    k = stage.base
    at, v = k + j, k + j + 1
    mine = f"{sequence}_par"
    guard = f"{sequence} >= {k} && {mine} < {v}" if k else f"{mine} < {v}"
    if step.condition is not None:
        guard += f" && ({expr(step.condition)})"
    action = INVERSE[step.action.text] if reverse else step.action.text
    arg = expr(step.args[0])
    if action == "waitUntil":
        act = f"if ({guard} && ({arg})) {{ {mine} := {v}; }}"
    else:
        if action == "turnQuarters" and reverse:
            arg = f"0 - ({arg})"
        act = f"if ({guard}) {{ if (self.{action}({arg})) {{ {mine} := {v}; }} }}"
    count = f"if ({sequence} == {at} && {mine} == {v}) {{ {sequence} := {v}; }}"
    return act, count


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
                reverse: bool = False, compact: bool = False,
                played: set[str] | None = None) -> dict[str, list[tuple[str, Span]]]:
    """Per deployed role, the generated members' text with the span they stand for (``compact``:
    the roles that can, as a table: rdcd_core/sequences/compact.py). ``played``: the roles that
    modules play while the sequence runs (``roles_played``); the others need no relay."""
    name = sequence.name.text
    steps = ordered_steps(sequence, reverse)
    ahead = ahead_steps(sequence, reverse)
    counted = count_order(steps, ahead)
    tables = {role: found for role in deployed if compact and applies(sequence)
              and (found := role_table(name, counted, role, reverse, is_rollback(sequence), ahead))
              is not None}
    # a step that acts ahead (a block's second) reads its lane: every block step in a table, or
    # none (the ordinary form's parallel code and the lanes count alike, but act on other states)
    if any(steps[k].role.text not in tables or steps[k].action.text == "waitUntil"
           for b in ahead.values() for k in (b, b + 1)):
        tables = {}
    out: dict[str, list[tuple[str, Span]]] = {
        role: [(f"behavior {name}_relay() {{ {name} := max({name}, max(neighbours.{name})); "
                f"{tables[role][0] if role in tables else ''} }}", sequence.header_span)]
        for role in deployed if played is None or role in played or role in tables}
    out.update({role: [] for role in deployed if role not in out})
    for role, (_, startup, acts) in tables.items():  # the module's key, the kinds of action
        if startup is not None:
            out[role].append((f"startup {name}_k_{role}() {{ {startup} }}", sequence.header_span))
        out[role] += acts
    by_role: dict[str, list[tuple[str, Span, bool]]] = {}  # code, span, in a behaviour alone

    def add(step: ast.SeqStep, code: str | None, alone: bool) -> None:
        if step.role.text in tables and step.action.text != "waitUntil":
            return  # in the role's table
        if code is not None and step.role.text in out:
            by_role.setdefault(step.role.text, []).append((code, step.span, alone))

    n = len(steps)
    rollback = is_rollback(sequence)
    if not rollback:
        for stage in progress_plan(sequence, reverse):
            for j, step in enumerate(stage.steps):
                if j:  # acts at once: two behaviours of their own (longer code)
                    for code in parallel_code(name, stage, j, step, reverse) or ():
                        add(step, code, True)
                else:  # a step alone (or a block's first, counted at the block's first value);
                    # one with a condition (or waitUntil's) takes a behaviour alone
                    add(step, step_code(name, stage.base, step, reverse),
                        step.condition is not None or step.action.text == "waitUntil")
    for k, step in enumerate(steps if rollback else ()):
        # rollback: progress 2n - 1 - j means "undo step j next"; a failure at step k undoes k - 1
        # first, and 2n is "rolled back" — the progress still only grows, so max() still spreads
        # it (progress.undo_value); the last step's undo never runs: nothing can fail after it
        add(step, step_code(name, k, step, reverse, failed=undo_value(n, k - 1)), True)
        if step.action.text != "waitUntil" and k < n - 1:  # with its failure branch: a behaviour
            add(step, step_code(name, k, step, not reverse, at=undo_value(n, k),
                                then=undo_value(n, k - 1)), True)
        elif k < n - 1:  # a wait has nothing to undo: the rollback goes on past it at once
            add(step, f"if ({name} == {undo_value(n, k)}) {{ {name} := {undo_value(n, k - 1)}; }}", False)
    for role, codes in by_role.items():
        chunks: list[list[tuple[str, Span, bool]]] = [[]]
        for item in codes:
            last = chunks[-1]
            if last and (len(last) == STEPS_PER_BEHAVIOUR or item[2] or last[0][2]):
                chunks.append([])
            chunks[-1].append(item)
        for i, chunk in enumerate(chunks):
            body = " ".join(code for code, _, _ in chunk)
            out[role].append((f"behavior {name}_{role}_{i}() {{ {body} }}", chunk[0][1]))
    return out


def roles_played(model: Any, sequence: ast.Sequence) -> set[str] | None:
    """The roles modules play while ``sequence`` runs, in the checker's model from the starting
    configuration the sequence names (rdcd_core/sequences/check.py): before each step and at the
    end. None when that is not known: no configuration named, one that cannot be loaded, a step
    that cannot happen, or a role that depends on values known only at run time."""
    from rdcd_core.sequences.check import own_run

    if model.has_errors:
        return None
    trace = own_run(model, sequence)  # the check's own run when it has just made it
    if trace is None:
        return None
    return trace.played if trace.final is not None and not trace.diagnostics else None


def lower(program: ast.Program, reverse: str | None = None, compact: bool = False,
          played: dict[str, set[str] | None] | None = None) -> ast.Program:
    """``program`` with its sequences as state and behaviours (``reverse``: the name of a sequence
    to run backwards instead). ``played``: per sequence, the roles modules play while it runs;
    in the compact form a role that none plays, one taken only after the sequence, gets no relay
    (roles_played; None: every deployed role relays)."""
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
        if any(stage.block for stage in progress_plan(sequence)) and \
                not any(s.name.text == f"{name}_par" for s in program.states):
            states.append(_respan(_state(f"{name}_par"), sequence.name.span))  # see parallel_code
        generated = members_for(sequence, [r for r in deployed if r in decls], parents,
                                reverse == name, compact, (played or {}).get(name))
        if compact and applies(sequence) and not any(s.name.text == f"{name}_t" for s in program.states):
            # the tables' states (see compact.py), those the generated code uses: none when no
            # role's steps took a table
            code = " ".join(text for items in generated.values() for text, _ in items)
            used = set(re.findall(r"\w+", code))
            for added in (f"{name}_t", f"{name}_k", f"{name}_a"):
                if added in used and not any(s.name.text == added for s in states):
                    states.append(_respan(_state(added), sequence.name.span))
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


def lowered_model(model: Any, reverse: str | None = None, compact: bool = False) -> Any:
    """The model of the program with its sequences lowered (analysed again)."""
    from rdcd_core.semantics import analyze

    # the compact form is for programs that do not fit: there a role taken only once a sequence
    # is done (found by the checker's model) spends no command number and no bytes on its relay
    played = {s.name.text: roles_played(model, s) for s in model.program.sequences} if compact else None
    return analyze(lower(model.program, reverse, compact, played))
