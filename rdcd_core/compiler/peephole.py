"""The peephole optimiser: jump threading, dead code, fused instructions, shared tails.

Works on code lists (``ir``) before layout, to a fixed point; bodies are optimised too.
"""

from __future__ import annotations

from operator import is_

from rdcd_core.compiler.geometry import ROLE_DIRECTION_OPS
from rdcd_core.compiler.ir import COND_JUMPS, ENDS_FLOW, JUMPS, Ins, Item, Label, bodies_of
from rdcd_core.compiler.tails import merge_tails

FLIP = {"IF_FALSE_GOTO": "IF_TRUE_GOTO", "IF_TRUE_GOTO": "IF_FALSE_GOTO"}
PURE_PUSH = {"PUSH", "COORD_X", "COORD_Y", "COORD_Z", "CONNECTED", "CONNECTED_SIZEOF",
             "CONNECTED_DIR", "CONNECTED_DIR_SIZEOF", "HAS_ROLE", "CONNECTED_ROLE",
             "CENTER_POSITION_EW", "CENTER_POSITION_NS", "CENTER_POSITION_UD", *ROLE_DIRECTION_OPS.values()}
COORD_OPS = {"COORD_X": "X", "COORD_Y": "Y", "COORD_Z": "Z"}
MIRROR_CMP = {"GREATER": "LESSER", "LESSER": "GREATER"}
FUSED_LAST = {*COND_JUMPS, "SIZEOF", "EQUALS", *MIRROR_CMP}  # the last instruction of every pattern


MAX_ROUNDS = 50


def optimise(code: list[Item]) -> list[Item]:
    """The code after the passes have run to a fixed point (at most MAX_ROUNDS rounds).

    Each body is optimised once and marked: the planner measures the same bodies in many trial
    fragments, and optimising one again would change nothing. (A body with thousands of shared
    tails may use up its rounds; they are a budget per body, so the result does not depend on how
    often the planner measured it.)
    """
    for body in bodies_of(code):
        if not body.optimised:
            body.code[:] = optimise(body.code)
            body.optimised = True
    # A pass is a function of the items alone: one that changed nothing on the code as it is now
    # would change nothing again, so a round stops as soon as every pass has run on the current
    # code without changing it (the passes after the last change in a round ran on it already).
    unchanged_by = [False] * len(PASSES)
    for _ in range(MAX_ROUNDS):
        for index, apply in enumerate(PASSES):
            if unchanged_by[index]:
                continue
            after = apply(code)
            if _same_items(code, after):
                unchanged_by[index] = True
                if all(unchanged_by):
                    return code
            else:
                code = after
                unchanged_by = [False] * len(PASSES)
    return code


def _same_items(before: list[Item], after: list[Item]) -> bool:
    """The same items in the same order. A pass makes a new instruction only where it changes the
    code (a new operation or target, never an equal copy), so this is "the pass changed nothing"."""
    return len(before) == len(after) and all(map(is_, before, after))


def _referenced(code: list[Item]) -> set[int]:
    return {id(item.args[0]) for item in code if type(item) is Ins and item.op in JUMPS}


def _falls_to(code: list[Item], index: int, label: Label) -> bool:
    """Only labels stand between the instruction at ``index`` and ``label``. (Scans the labels
    right after ``index`` only: each run of labels follows one instruction, so a pass that asks
    this for each of its instructions stays linear. Slicing the rest of the code made it quadratic.)"""
    for position in range(index + 1, len(code)):
        item = code[position]
        if item is label:
            return True
        if type(item) is Ins:
            return False
    return False


def _first_instructions(code: list[Item]) -> dict[int, int | None]:
    """id(label) -> the position of the first instruction at or after the label's first position
    (None: none follows), for a code list whose instructions may be replaced but not moved. One
    backward scan: searching the code for each jump made threading quadratic."""
    first: dict[int, int | None] = {}
    following: int | None = None
    for index in range(len(code) - 1, -1, -1):
        item = code[index]
        if type(item) is Ins:
            following = index
        else:  # a label seen twice keeps its first position: the scan runs backwards
            first[id(item)] = following
    return first


def _thread(code: list[Item]) -> list[Item]:
    code = list(code)
    targets = _first_instructions(code)
    for index, item in enumerate(code):
        if type(item) is not Ins or item.op not in JUMPS:
            continue
        for _ in range(8):
            dest_index = targets.get(id(item.args[0]))
            if dest_index is None:
                break
            dest = code[dest_index]
            if dest.op == "GOTO" and dest.args[0] is not item.args[0]:
                item = Ins(item.op, (dest.args[0],), item.span)
            elif (item.op == "GOTO" and dest.ends_flow and dest.size == 1
                  and not _falls_to(code, index, item.args[0])):
                item = Ins(dest.op, (), dest.span)
                break
            else:
                break
        code[index] = item
    return code


def _drop_dead(code: list[Item]) -> list[Item]:
    """Code after an instruction that ends the flow, up to a label in use; labels not in use; a
    GOTO to the very next instruction (only labels between them)."""
    used = _referenced(code)
    result: list[Item] = []
    append = result.append
    dead = False
    last_ins = -1  # position in result of the last instruction kept
    goto_next: list[int] = []  # positions in result of GOTOs to the very next instruction
    for item in code:
        if type(item) is Label:
            if id(item) in used:
                dead = False
                if last_ins >= 0 and result[last_ins].op == "GOTO" and result[last_ins].args[0] is item \
                        and (not goto_next or goto_next[-1] != last_ins):
                    goto_next.append(last_ins)
                append(item)
            continue
        if not dead:
            last_ins = len(result)
            append(item)
            dead = item.op in ENDS_FLOW
    if not goto_next:
        return result
    dropped = set(goto_next)
    return [item for index, item in enumerate(result) if index not in dropped]


def _skip_over_goto(code: list[Item]) -> list[Item]:
    """IF_X L1; GOTO L2; L1:  ->  IF_notX L2; L1:"""
    result = list(code)
    for index in range(len(result) - 2):
        first, second = result[index], result[index + 1]
        if (type(first) is Ins and first.op in COND_JUMPS and type(second) is Ins
                and second.op == "GOTO" and _falls_to(result, index + 1, first.args[0])):
            result[index] = Ins(FLIP[first.op], second.args, first.span)
            result[index + 1] = Ins("NOP")
    return [item for item in result if not (type(item) is Ins and item.op == "NOP")]


def _fuse(code: list[Item]) -> list[Item]:
    result: list[Item] = []
    for item in code:
        result.append(item)
        if type(item) is Ins and item.op in FUSED_LAST:
            _fuse_tail(result)
    return result


def _fuse_tail(out: list[Item]) -> None:
    """Rewrites the last two or three instructions of ``out`` when a pattern matches."""
    if len(out) < 2:
        return
    a, b = out[-2], out[-1]
    if not (type(a) is Ins and type(b) is Ins):
        return
    span = a.span or b.span
    if a.op == "EQUALS_0" and b.op in COND_JUMPS:
        out[-2:] = [Ins(FLIP[b.op], b.args, b.span)]
    elif a.op in ("CONNECTED_DIR", "CONNECTED") and b.op == "SIZEOF":
        out[-2:] = [Ins(a.op + ("_SIZEOF"), a.args, span)]
    elif a.op == "SIZEOF" and b.op in COND_JUMPS:
        out[-2:] = [b]
        _fuse_tail(out)
    elif a.op == "PUSH" and 0 <= a.args[0] <= 4 and b.op == "EQUALS":
        out[-2:] = [Ins(f"EQUALS_{a.args[0]}", (), span)]
    elif a.op == "CONNECTED_ROLE" and b.op in COND_JUMPS and a.args[0] in ROLE_DIRECTION_OPS:
        out[-2:] = [Ins(ROLE_DIRECTION_OPS[a.args[0]], (a.args[1],), a.span), b]
    elif len(out) >= 3 and type(out[-3]) is Ins and b.op in MIRROR_CMP:
        _fuse_compare(out)


def _fuse_compare(out: list[Item]) -> None:
    first, second, cmp = out[-3], out[-2], out[-1]
    if first.op in COORD_OPS and second.op in PURE_PUSH and second.op not in COORD_OPS:
        out[-3:] = [second, Ins(f"COORD_{COORD_OPS[first.op]}_{cmp.op}", (), cmp.span)]
    elif second.op in COORD_OPS and first.op in PURE_PUSH and first.op not in COORD_OPS:
        out[-3:] = [first, Ins(f"COORD_{COORD_OPS[second.op]}_{MIRROR_CMP[cmp.op]}", (), cmp.span)]


# one round, in order (a round runs them all, or stops where the code is known to be final)
PASSES = (_fuse, _drop_dead, _skip_over_goto, _thread, merge_tails)
