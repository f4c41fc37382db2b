"""The compact form of a sequence (docs/reconfiguration.md "The compact form"): the steps of a
role as a table, one byte a step, instead of a comparison and a branch per step.

Used when the ordinary form (rdcd_core/sequences/lower.py) does not fit a module's program slots
(E805, E121, a fragment over the budget: W601) and the target runs TABLE and ACT. For a role R
whose steps (other than waitUntil's) all name their module alike, a startup keeps the module's
key once (``S_k := (E) * 14;``) and the relay of R also reads its step code at the progress S::

    S_t := table(S - k0, e_k0, ..., e_k0+8) - S_k; S_t := S_t + table(S - k0 - 9, ...);

with k0..k1 R's first and last steps; e = key * 14 + a (0: not R's step), where key is the value
of the condition's left side that names the module (``R(E == key)``, 0..8; 0 without a condition)
and a the action: disconnect(c) 1 + c/2, connect(c) 5 + c/2 (male c 0..6), turnQuarters(n)
11 + n (n = -2, -1, 1, 2), the codes of the DCD-VM's ACT (vm.isa.opcodes.step_action). After
the subtraction S_t is a (1..13) on the module of the step only, 14 or more away (or <= 0) on
the others, where ACT answers false at once doing nothing; one behaviour acts::

    if (self.act(S_t)) { S := S + 1; S_t := 0; }

Only the module of step S can move the progress past S, so the code it read stays the code of the
step until it acts; ``S_t := 0`` keeps a second run before the next read from acting twice. A
failed action leaves S, and is tried again. Backwards (``reverse``) the table is the undo of each
step, read in reverse order.

``rollback`` keeps the ordinary form's numbering (lower.py, docs "Rolling back from a program",
progress.undo_value): with n steps the table also holds the undo of step k < n - 1 at progress
2n - 1 - k (entry n is 0, and the two runs of entries are one table when few zeros lie between),
and the behaviour that acts has a second statement (the splitter may cut between the two)::

    if (S_t > 0 && S_t < 14 && S < n) { S := 2n - S; S_t := 0; }

after a failed act S_t still holds the step's code, on the step's module only: a failed step k
sets 2n - k ("undo step k - 1 next") and is not tried again; past n a failed undo leaves S, and
is read and tried again; 2n (rolled back) is outside every table. A parallel block of a
rollback sequence runs one step after the other, so it takes the compact form too.

Without rollback a parallel block of two steps (counted at b and b + 1, lower.py) takes the form
too: its second step also has its code in a *lane*, a second table the relay reads into ``S_a``,
at b; the behaviour that acts first counts that step once its module has done it and the table
reads a code there (``COUNT``), then acts on the lane once (``LANE``), then on the table. A
sequence with a larger block keeps the ordinary form."""

from __future__ import annotations

from rdcd_core.formatter import expr
from rdcd_core.sequences.check import INVERSE, STEP_ACTIONS
from rdcd_core.sequences.progress import is_rollback, progress_plan, undo_value
from rdcd_core.source import Span
from rdcd_core.syntax import ast
from vm.isa.opcodes import step_action

CODES = 14  # a in 1..13; key * 14 + 13 <= 127 for a key up to 8
MAX_KEY = (127 - (CODES - 1)) // CODES
# entries of a table statement, the first after the relay: each statement fits a fragment's part
# (43 bytes: the part's 11, the statement's 12 and 2 to go on to the next part leave 18; the last
# part ends in 1 byte, so its statement holds 19)
FIRST, CHUNK = 9, 18
# one behaviour acts on every code (the DCD-VM's ACT, vm.isa.opcodes.step_action, decodes it):
# one command number for the role's actions, where a behaviour per kind took three
ACT = "if (self.act({t})) {{ {name} := {name} + 1; {t} := 0; }}"
# rollback: after a failed act, S_t still holds the step's code (1..13) on the module of the step
# only (ACT does nothing for any other value, a success sets it 0); at a forward step k (< n) the
# progress goes to 2n - k, "undo step k - 1 next", and the step is not tried again. An undo
# (progress > n) that fails leaves S_t to be read again: it is tried again.
FAILED = "if ({t} > 0 && {t} < {codes} && {name} < {n}) {{ {name} := {back} - {name}; {t} := 0; }}"
# zeros between the forward and the undo entries that cost less than a table statement of their own
UNDO_GAP = 4
# a parallel block's second step reads its code from a second table, the lane, from the block's
# first value on (``role_table``); a block of more steps keeps the ordinary form
LANES = 1
# the lane's step acts once, ahead, and is counted in its turn. The lane holds its code at the
# block's first value b only; S_par says the module has done it (1). Counted when the table reads
# a code (> 0) on that module, which it does at b + 1, its own value, only: at b the table holds
# the block's first step, of a module with a smaller key (``count_order``), or of another role
# (0), so the read there is <= 0. In this order: counted; the lane (S_t := 0 when it acted, for
# the relay may have read the step's own code meanwhile); the table (``ACT``)
COUNT = "if ({d} == 1 && {t} > 0) {{ {name} := {name} + 1; {t} := 0; {d} := 0; }}"
LANE = "if ({d} == 0) {{ if (self.act({a})) {{ {d} := 1; {t} := 0; }} }}"


def applies(sequence: ast.Sequence) -> bool:
    """The sequences with a compact form: with ``rollback`` (the steps of a parallel block run
    one after the other, progress.progress_plan), or whose parallel blocks have at most two steps
    (the second acts ahead from its lane, see ``role_table``)."""
    return is_rollback(sequence) or all(isinstance(item, ast.SeqStep) or len(item.steps) <= LANES + 1
                                        for item in sequence.items)


def count_order(steps: list[ast.SeqStep], ahead: dict[int, int]) -> list[ast.SeqStep]:
    """The steps in the order they are counted in tables: a block of two steps of one role is
    counted smaller key first (they act at once, either order ends in the same structure, E816),
    so that on the second step's module the table reads <= 0 at the block's first value."""
    out = list(steps)
    for b in ahead.values():
        first, second = _key(out[b]), _key(out[b + 1])
        if out[b].role.text == out[b + 1].role.text and first and second and first[1] > second[1]:
            out[b], out[b + 1] = out[b + 1], out[b]
    return out


def ahead_steps(sequence: ast.Sequence, reverse: bool = False) -> dict[int, int]:
    """Per step number (as the steps run) that acts ahead, the first progress value at which it
    may act: the second step of each parallel block (not with ``rollback``)."""
    if is_rollback(sequence):
        return {}
    return {stage.base + 1: stage.base for stage in progress_plan(sequence, reverse)
            if stage.block and len(stage.steps) == LANES + 1}


def _constant(node: ast.Node) -> int | None:
    text = expr(node).replace(" ", "")
    try:
        return int(text)
    except ValueError:
        return None


def _key(step: ast.SeqStep) -> tuple[str | None, int] | None:
    """(the left side that names the module, its value), (None, 0) without a condition."""
    if step.condition is None:
        return None, 0
    cond = ast.unparen(step.condition)
    if isinstance(cond, ast.Binary) and cond.op == "==":
        value = _constant(cond.right)
        if value is not None and 0 <= value <= MAX_KEY:
            return expr(cond.left), value
    return None


def _step_code(action: str, arg: int, inverse: bool) -> int | None:
    """The ACT code of a step, or of its undo (``inverse``: the inverse action, the turn negated)."""
    if inverse:
        action = INVERSE[action]
        if action == "turnQuarters":
            arg = -arg
    return _code(action, arg)


def _code(action: str, arg: int) -> int | None:
    """The ACT code of a step: the one the DCD-VM decodes (step_action) as this action, if any."""
    kind = "turn" if action == "turnQuarters" else action
    return next((a for a in range(1, CODES) if step_action(a) == (kind, arg)), None)


def _ranges(spans: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The progress values the table statements cover: each span (first, last), two joined when
    the zeros between them cost less than a statement of their own."""
    out: list[tuple[int, int]] = []
    for first, last in sorted(spans):
        if out and first - out[-1][1] - 1 <= UNDO_GAP:
            out[-1] = (out[-1][0], max(out[-1][1], last))
        else:
            out.append((first, last))
    return out


def role_table(name: str, steps: list[ast.SeqStep], role: str, reverse: bool,
               rollback: bool = False, ahead: dict[int, int] | None = None,
               ) -> tuple[str, str | None, list[tuple[str, Span]]] | None:
    """(the table read after the relay, the key's startup statement, the behaviours that act) of
    ``role``'s steps, None when one of them has no compact code (its condition is not
    ``E == key``, or another E, or an argument outside the codes). ``rollback``: with n steps,
    the table also holds the undo of step k < n - 1 at progress 2n - 1 - k, and the behaviour that
    acts sets the progress to 2n - k when step k fails (progress.undo_value, "Rolling back").
    ``ahead`` (``ahead_steps``): a step k that acts from progress b on, the second of a parallel
    block (``steps`` in ``count_order``); its code is also in the lane, a second table the relay
    reads into ``S_a`` (at b the step's code), and the behaviour that acts counts it, acts on the
    lane once, then acts on the table (``COUNT``, ``LANE``)."""
    mine = [(k, s) for k, s in enumerate(steps) if s.role.text == role and s.action.text != "waitUntil"]
    if not mine:
        return None
    ahead = ahead or {}
    n = len(steps)
    left: set[str | None] = set()
    entries: dict[int, int] = {}
    lane: dict[int, int] = {}
    for k, step in mine:
        if step.action.text not in STEP_ACTIONS or len(step.args) != 1:
            return None
        key = _key(step)
        arg = _constant(step.args[0]) if not isinstance(step.args[0], ast.Block) else None
        if key is None or arg is None:
            return None
        code = _step_code(step.action.text, arg, reverse)
        undo = _step_code(step.action.text, arg, not reverse) if rollback else 0
        if code is None or undo is None:
            return None
        left.add(key[0])
        entries[k] = key[1] * CODES + code
        if rollback and k < n - 1:  # the undo of step k runs at 2n - 1 - k; the last step's never
            entries[undo_value(n, k)] = key[1] * CODES + undo
        if k in ahead:
            lane[ahead[k]] = entries[k]
    if len(left) != 1:
        return None
    k0, k1 = mine[0][0], mine[-1][0]
    # rollback: the undos in a second run of entries, 2n - k1..2n - k0 (one table indexed by
    # min(S, 2n - S) with the code turned into its undo's past n was measured larger: car_to_snake
    # 206 bytes and a fragment that cannot be split, against 168)
    undos = [undo_value(n, k) for k, _ in mine if k < n - 1] if rollback else []
    spans = [(k0, k1)] + ([(min(undos), max(undos))] if undos else [])
    t = f"{name}_t"
    side = left.pop()
    k = f"{name}_k"
    reads = _reads(t, name, entries, _ranges(spans), f" - {k}" if side else "", not lane)
    if lane:  # each block's first value, two runs joined when few zeros lie between
        runs = _ranges([(v, v) for v in sorted(lane)])
        reads += _reads(f"{name}_a", name, lane, runs, f" - {k}" if side else "")
    read = " ".join(reads)
    # the module's key times 14, once: S_t is then a (1..13) on the module whose step it is
    # only; on the others 14 or more away (or <= 0)
    startup = f"{k} := ({side}) * {CODES};" if side else None
    # ACT answers false at once, doing nothing, for a code that is no step's (0, <= 0 or >= 14
    # away from this module's key): the modules whose step it is not
    act = ACT.format(t=t, name=name)
    if lane:  # counted, the lane, then the table (COUNT, LANE)
        act = " ".join([COUNT.format(d=f"{name}_par", t=t, name=name),
                        LANE.format(d=f"{name}_par", a=f"{name}_a", t=t), act])
    if rollback:  # a second statement, so that the splitter may cut between the two
        act += " " + FAILED.format(t=t, name=name, n=n, back=2 * n, codes=CODES)
    acts = [(f"behavior {t}_{role}() {{ {act} }}", mine[0][1].span)]
    return read, startup, acts


def _reads(state: str, name: str, entries: dict[int, int], ranges: list[tuple[int, int]],
           minus: str, ends: bool = True) -> list[str]:
    """The table statements that read ``state`` at the progress: the first into the state (less
    the key, ``minus``), the others added; each table covers its range, 0 outside. ``ends``: the
    last statement ends the relay, in a part with a byte to spare, which holds one entry more
    rather than leave it to a statement of its own."""
    reads: list[str] = []  # the first statement follows the relay in the behaviour's first part
    for i, (first, last) in enumerate(ranges):
        start = first
        while start <= last:
            size = CHUNK if reads else FIRST
            if reads and ends and i == len(ranges) - 1 and last + 1 - start == CHUNK + 1:
                size += 1
            end = min(start + size, last + 1)
            values = ", ".join(str(entries.get(j, 0)) for j in range(start, end))
            index = f"{name} - {start}" if start else name
            reads.append(f"{state} := {state} + table({index}, {values});" if reads
                         else f"{state} := table({index}, {values}){minus};")
            start = end  # one index in its table: outside it, table() is 0
    return reads
