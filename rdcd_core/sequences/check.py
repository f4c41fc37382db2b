"""The checks of reconfiguration sequences (docs/reconfiguration.md).

``check_names``: what the program alone says (E801..E803). ``run`` takes a sequence through the
lattice model from a starting structure, step by step, with the operations of
``vm.lattice.changes`` on a copy: which module acts (by the role it holds, found as the VM finds
it), and whether the step can happen (E810..E816, W810). The structure after each step is kept for
the editor's hover.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import partial
from typing import Any

from rdcd_core import diagnostics as diag
from rdcd_core.module_api import ACTIONS
from rdcd_core.semantics.model import Model
from rdcd_core.sequences import codes
from rdcd_core.sequences.roles import entry_frame, environment, evaluate, find_roles
from rdcd_core.syntax import ast

STEP_ACTIONS = ("connect", "disconnect", "turnQuarters", "waitUntil")
# the inverse of each action, for running a sequence backwards (docs/reconfiguration.md)
INVERSE = {"connect": "disconnect", "disconnect": "connect", "turnQuarters": "turnQuarters",
           "waitUntil": "waitUntil"}
MAX_STEPS = 60  # the progress value of a step fits a signed byte with room for a rollback


def stages(sequence: ast.Sequence) -> list[tuple[ast.SeqStep, ...]]:
    """The stages in order: a step alone, or the steps of a parallel block (empty ones dropped)."""
    out = []
    for item in sequence.items:
        steps = (item,) if isinstance(item, ast.SeqStep) else item.steps
        if steps:
            out.append(tuple(steps))
    return out


def steps_of(sequence: ast.Sequence) -> Iterator[ast.SeqStep]:
    for stage in stages(sequence):
        yield from stage


def constant_arg(step: ast.SeqStep, model: Model) -> int | None:
    """The integer argument of connect, disconnect and turnQuarters, or None if not a constant."""
    if len(step.args) != 1 or any(isinstance(n, (ast.SelfCall, ast.FunctionCall, ast.GlobalCall,
                                                 ast.NeighbourValues, ast.Block))
                                  for n in ast.walk(step.args[0])):
        return None
    value = evaluate(step.args[0], model, step.role.text, None, -1)  # type: ignore[arg-type]
    return value if isinstance(value, int) else None


# module states each sequence S declares for itself (E801 when the program declares one)
RESERVED = {"_par": "the steps done in a parallel block", "_t": "the step code of the compact form",
            "_k": "the module's key in the compact form",
            "_a": "the step code of a parallel block's second step in the compact form"}


def check_names(model: Model) -> list[diag.Diagnostic]:
    found: list[diag.Diagnostic] = []
    seen: dict[str, ast.Sequence] = {}
    for sequence in model.program.sequences:
        name = sequence.name.text
        state = model.states.get(name)
        generated = state is not None and state.decl.span == sequence.name.span  # lower.py's own
        if name in seen or (state is not None and not generated):
            found.append(diag.make(codes.DUPLICATE_SEQUENCE, sequence.name.span,
                                   f"'{name}' is already the name of a "
                                   f"{'sequence' if name in seen else 'module state'}"))
        seen.setdefault(name, sequence)
        for suffix, use in RESERVED.items():  # the lowering's own states (lower.py, compact.py)
            other = model.states.get(name + suffix)
            if other is not None and other.decl.span != sequence.name.span:
                found.append(diag.make(codes.DUPLICATE_SEQUENCE, other.decl.name.span,
                                       f"'{name}{suffix}' is the name sequence '{name}' uses for "
                                       f"{use}: give this state another name"))
        if sequence.modifier is not None and sequence.modifier.text != "rollback":
            found.append(diag.make(codes.BAD_STEP, sequence.modifier.span,
                                   f"'{sequence.modifier.text}': after a sequence's name and "
                                   "configuration only 'rollback' may stand"))
        count = sum(1 for _ in steps_of(sequence))
        if count > MAX_STEPS:
            found.append(diag.make(codes.BAD_STEP, sequence.name.span,
                                   f"sequence '{name}' has {count} steps; at most {MAX_STEPS}"))
        for step in steps_of(sequence):
            found += _check_step(model, step)
    return found


def _check_step(model: Model, step: ast.SeqStep) -> list[diag.Diagnostic]:
    role, action = step.role.text, step.action.text
    if role not in model.deployment:
        known = ", ".join(model.deployment) or "none"
        return [diag.make(codes.UNKNOWN_STEP_ROLE, step.role.span,
                          f"no role '{role}' in the deployment (deployed: {known}): a step names "
                          "the acting module by a role it can hold")]
    if action not in STEP_ACTIONS:
        return [diag.make(codes.BAD_STEP, step.action.span,
                          f"'{action}' is not a step's action: connect(c), disconnect(c), "
                          "turnQuarters(n) or waitUntil(condition)")]
    bad = [n for n in (*step.args, *([step.condition] if step.condition is not None else []))
           for n in ast.walk(n) if isinstance(n, ast.SelfCall) and n.name.text in ACTIONS]
    if bad:
        return [diag.make(codes.BAD_STEP, bad[0].span,
                          "a condition cannot act: connect, disconnect and turnQuarters are the "
                          "step's action")]
    if action == "waitUntil":
        if len(step.args) != 1 or isinstance(step.args[0], ast.Block):
            return [diag.make(codes.BAD_STEP, step.span, "waitUntil takes one condition")]
        return []
    value = constant_arg(step, model)
    if action == "turnQuarters":
        if value is None or value == 0 or not -3 <= value <= 3:
            return [diag.make(codes.BAD_STEP, step.span,
                              "turnQuarters takes a constant number of quarter turns: -3..3, not 0")]
        return []
    if value is None or value not in (0, 2, 4, 6):
        return [diag.make(codes.BAD_STEP, step.span,
                          f"{action} takes a constant male connector: 0, 2, 4 or 6 (only a male "
                          "connector latches and unlatches)")]
    return []


# ----------------------------------------------------------------------------- the lattice run


@dataclass
class StepResult:
    step: ast.SeqStep
    module: int | None  # the acting module (None: not found)
    # the structure after the step, as text, written when first asked for (hover): a check that
    # nobody hovers does not pay for finding every module's role after every step
    describe: Callable[[], str] = field(default=lambda: "", repr=False)
    _after: str | None = field(default=None, repr=False)

    @property
    def after(self) -> str:
        """The structure after the step, as text ("" when the run stopped before)."""
        if self._after is None:
            self._after = self.describe()
        return self._after


@dataclass
class Trace:
    results: list[StepResult] = field(default_factory=list)
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    final: Any = None  # the Structure after the last step, when every step could happen
    start: Any = None
    # the roles modules play before each step and at the end; None when a module's role depends
    # on values known only at run time (the compact form's relays, rdcd_core/sequences/lower.py)
    played: set[str] | None = field(default_factory=set)
    # what each module knows of its place where the run ended (roles.py ``entry_frame``): a module
    # keeps what it learned while it keeps a connection; the place a run backwards starts from
    learned: dict[int, Any] = field(default_factory=dict)


def load_structure(name: str) -> Any:
    """The Structure of a configuration name or file; a ValueError (one line) when it cannot be."""
    from sim.config import load_config  # configurations live with the simulator (read-only use)

    return load_config(name)


def run(model: Model, sequence: ast.Sequence, structure: Any, *, reverse: bool = False,
        learned: dict[int, Any] | None = None) -> Trace:
    """Takes ``sequence`` through a copy of ``structure``; stops at the first step that cannot
    happen (the structure after it is not known). ``learned``: what each module knows of its place
    at the start (default: the entry module's frame, as when the program enters there)."""
    current = structure.copy()
    trace = Trace(start=structure)
    # what each module knows of its place (roles.py); the trace keeps it up to date
    learned = dict(learned) if learned is not None else entry_frame(structure)
    trace.learned = learned
    order = stages(sequence)
    if reverse:
        order = [tuple(reversed(stage)) for stage in reversed(order)]
    for stage in order:
        # a module that acts or is carried must not take part in another step of the block; the
        # far end of a latch may be the far end of another latch (other connectors, other links)
        acting: dict[int, ast.SeqStep] = {}
        ends: dict[int, ast.SeqStep] = {}
        for step in stage:
            ok, mid, touches = _one_step(model, step, current, trace, reverse, learned)
            if not ok:
                return trace
            moves, far = touches
            for other in sorted(moves | far):
                earlier = acting.get(other) or (ends.get(other) if other in moves else None)
                if earlier is not None and len(stage) > 1:
                    trace.diagnostics.append(diag.make(
                        codes.SHARED, step.span,
                        f"this step and an earlier one of its parallel block both touch module "
                        f"{other}: make them one after the other",
                        related=(diag.Related(earlier.span, "the other step"),)))
                    return trace
            acting.update((other, step) for other in moves)
            ends.update((other, step) for other in far)
            for other in current.modules:  # a module alone learns its place again when attached
                if not current.neighbours(other):
                    learned.pop(other, None)
                elif other not in learned:
                    learned[other] = current.modules[other]
            snapshot, known = current.copy(), dict(learned)
            trace.results.append(StepResult(step, mid, partial(describe, model, snapshot, known)))
    trace.final = current
    _played(trace, *find_roles(model, current, learned))
    return trace


def _played(trace: Trace, roles: dict[int, str | None], uncertain: set[int]) -> None:
    if trace.played is not None:
        trace.played = None if uncertain else trace.played | {r for r in roles.values() if r}


def backwards(model: Model, sequence: ast.Sequence, forward: Trace) -> Trace:
    """``sequence`` run backwards on the robot as its forward run ``forward`` leaves it: the end
    shape, every module holding the coordinates and orientation it knows there (those it learned
    at the start, while it kept a connection), so a role by position names the same module both
    ways (docs/reconfiguration.md "Backwards"). ``forward`` must have reached its end."""
    if forward.final is None:
        raise ValueError("the forward run did not reach the end of the sequence")
    return run(model, sequence, forward.final, reverse=True, learned=forward.learned)


Touches = tuple[set[int], set[int]]  # modules that act or are carried; far ends of a latch


def _one_step(model: Model, step: ast.SeqStep, current: Any, trace: Trace,
              reverse: bool, learned: dict[int, Any]) -> tuple[bool, int | None, Touches]:
    roles, uncertain = find_roles(model, current, learned)
    _played(trace, roles, uncertain)
    env = environment(model, current, roles, learned)
    sure, maybe = [], []
    for mid in sorted(current.modules):
        held = roles.get(mid)
        if held is None or not model.is_subrole(held, step.role.text):
            continue
        v = 1 if step.condition is None else evaluate(step.condition, model, held, env, mid)
        if mid in uncertain or v is None:
            maybe.append(mid)
        elif v:
            sure.append(mid)
    where = f" (condition {_text(step.condition)})" if step.condition is not None else ""
    if len(sure) > 1:
        trace.diagnostics.append(diag.make(
            codes.MANY_HOLDERS, step.role.span,
            f"modules {', '.join(map(str, sure))} hold {step.role.text}{where} here: a step needs "
            "exactly one; add a condition or a role that tells them apart"))
        return False, None, (set(), set())
    if not sure and not maybe:
        trace.diagnostics.append(diag.make(
            codes.NO_HOLDER, step.role.span,
            f"no module holds {step.role.text}{where} at this point of the sequence "
            f"(the roles here: {_roles_text(roles)})"))
        return False, None, (set(), set())
    if not sure and len(maybe) > 1 or maybe and sure:
        trace.diagnostics.append(diag.make(
            codes.UNCHECKED, step.role.span,
            f"which module holds {step.role.text}{where} depends on values known only at run time "
            "(modules " + ", ".join(map(str, sure + maybe)) + "): the rest of the sequence is not "
            "checked"))
        return False, None, (set(), set())
    mid = (sure or maybe)[0]
    action = INVERSE[step.action.text] if reverse else step.action.text
    if action == "waitUntil":
        return True, mid, ({mid}, set())
    value = constant_arg(step, model)
    if value is None:
        return False, mid, (set(), set())
    if action == "connect":
        change = current.latch(mid, value)
    elif action == "disconnect":
        change = current.unlatch(mid, value)
    else:
        change = current.rotate(mid, -value if reverse else value)
    if not change.ok:
        code = {"loop": codes.LOOP, "collision": codes.COLLISION, "ground": codes.COLLISION}.get(
            change.cause, codes.NO_LATCH)
        trace.diagnostics.append(diag.make(code, step.span, f"module {mid} ({roles.get(mid)}): "
                                           f"{change.reason or change.describe()}"))
        return False, mid, (set(), set())
    if change.parts:
        sizes = " and ".join("{" + ", ".join(map(str, sorted(p))) + "}" for p in change.parts)
        trace.diagnostics.append(diag.make(
            codes.SPLIT, step.span,
            f"module {mid} ({roles.get(mid)}) would split the robot into {sizes}: latch the part "
            "elsewhere first"))
        return False, mid, (set(), set())
    far = {change.link.a, change.link.b} - {mid} if change.link is not None else set()
    return True, mid, ({mid, *change.moved}, far)


def _text(expr: Any) -> str:
    from rdcd_core.formatter import expr as render

    return render(expr) if expr is not None else ""


def _roles_text(roles: dict[int, str | None]) -> str:
    return ", ".join(f"{m}: {r or '-'}" for m, r in sorted(roles.items()))


def describe(model: Model, structure: Any, learned: dict[int, Any] | None = None) -> str:
    """The structure as text: each module's cell, axis and role; the links."""
    from vm.navigation import AXIS_NAMES

    roles, _ = find_roles(model, structure, learned)
    lines = [f"module {m}: {tuple(s.position)} {AXIS_NAMES.get(s.axis, '?')} {roles.get(m) or '-'}"
             for m, s in sorted(structure.modules.items())]
    links = " ".join(f"{k.a}.{k.a_physical}-{k.b}.{k.b_physical}" for k in structure.links())
    return "\n".join(lines + [f"links: {links}"])


def lattice_diagnostics(model: Model, config: str | None,
                        loader: Callable[[str], Any] = load_structure) -> tuple[list[diag.Diagnostic],
                                                                                dict[int, Trace]]:
    """E804 and the run of every sequence that has a starting configuration (``config`` wins over
    the one a sequence names); the traces by the sequence's index."""
    found: list[diag.Diagnostic] = []
    traces: dict[int, Trace] = {}
    cache: dict[str, Any] = {}
    for index, sequence in enumerate(model.program.sequences):
        name = config or (sequence.config.text if sequence.config is not None else None)
        if name is None:
            continue
        if name not in cache:
            try:
                cache[name] = loader(name)
            except (ValueError, OSError) as error:
                cache[name] = str(error)
        structure = cache[name]
        if isinstance(structure, str):
            span = sequence.config.span if sequence.config is not None else sequence.name.span
            found.append(diag.make(codes.UNKNOWN_CONFIG, span, f"starting configuration: {structure}"))
            continue
        trace = run(model, sequence, structure)
        traces[index] = trace
        found += trace.diagnostics
        if loader is load_structure and sequence.config is not None and name == sequence.config.text:
            _remember(model, sequence, trace)
    return found, traces


# the last runs from a sequence's own starting configuration, by model (kept with it, so that its
# id cannot be reused): the compiler asks for the roles played (lower.roles_played) right after
# the check ran the same sequence on the same model
_RUNS: dict[int, tuple[Model, dict[str, Trace]]] = {}
_RUNS_KEPT = 4


def _remember(model: Model, sequence: ast.Sequence, trace: Trace) -> None:
    kept = _RUNS.get(id(model))
    if kept is None or kept[0] is not model:
        while len(_RUNS) >= _RUNS_KEPT:
            _RUNS.pop(next(iter(_RUNS)))
        kept = _RUNS[id(model)] = (model, {})
    kept[1][sequence.name.text] = trace


def own_run(model: Model, sequence: ast.Sequence) -> Trace | None:
    """The run of ``sequence`` from the starting configuration it names, on ``model``; None when
    it names none or that cannot be loaded."""
    kept = _RUNS.get(id(model))
    if kept is not None and kept[0] is model and sequence.name.text in kept[1]:
        return kept[1][sequence.name.text]
    if sequence.config is None:
        return None
    try:
        structure = load_structure(sequence.config.text)
    except (ValueError, OSError):
        return None
    trace = run(model, sequence, structure)
    _remember(model, sequence, trace)
    return trace

