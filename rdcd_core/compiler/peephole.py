"""The peephole optimiser: jump threading, dead code, fused instructions, shared tails.

Works on code lists (``ir``) before layout, to a fixed point; bodies are optimised too.
"""

from __future__ import annotations

from rdcd_core.compiler.geometry import ROLE_DIRECTION_OPS
from rdcd_core.compiler.ir import COND_JUMPS, JUMPS, Ins, Item, Label, bodies_of
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
    before = _keys(code)
    for _ in range(MAX_ROUNDS):
        code = _fuse(code)
        code = _drop_dead(code)
        code = _skip_over_goto(code)
        code = _thread(code)
        code = merge_tails(code)
        after = _keys(code)
        if before == after:
            break
        before = after
    return code


def _keys(code: list[Item]) -> list[object]:
    return [item.key() if isinstance(item, Ins) else id(item) for item in code]


def _referenced(code: list[Item]) -> set[int]:
    return {id(item.args[0]) for item in code if isinstance(item, Ins) and item.op in JUMPS}


def _falls_to(code: list[Item], index: int, label: Label) -> bool:
    """Only labels stand between the instruction at ``index`` and ``label``. (Scans the labels
    right after ``index`` only: each run of labels follows one instruction, so a pass that asks
    this for each of its instructions stays linear. Slicing the rest of the code made it quadratic.)"""
    for position in range(index + 1, len(code)):
        item = code[position]
        if item is label:
            return True
        if isinstance(item, Ins):
            return False
    return False


class _Targets:
    """The first instruction at or after each label, in a code list whose instructions may be
    replaced but not moved (searching the whole code for each jump made threading quadratic)."""

    def __init__(self, code: list[Item]) -> None:
        self.code = code
        self.label_at: dict[int, int] = {}  # id(label) -> its first position
        for index, item in enumerate(code):
            if isinstance(item, Label):
                self.label_at.setdefault(id(item), index)
        self.found: dict[int, int | None] = {}

    def first_ins(self, label: Label) -> int | None:
        if id(label) not in self.found:
            start = self.label_at.get(id(label), len(self.code))
            self.found[id(label)] = next(
                (i for i in range(start, len(self.code)) if isinstance(self.code[i], Ins)), None)
        return self.found[id(label)]


def _thread(code: list[Item]) -> list[Item]:
    code = list(code)
    targets = _Targets(code)
    for index, item in enumerate(code):
        if not isinstance(item, Ins) or item.op not in JUMPS:
            continue
        for _ in range(8):
            dest_index = targets.first_ins(item.args[0])
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
    used = _referenced(code)
    result: list[Item] = []
    dead = False
    for item in code:
        if isinstance(item, Label):
            if id(item) in used:
                dead = False
                result.append(item)
            continue
        if not dead:
            result.append(item)
            dead = item.ends_flow
    # a GOTO to the very next instruction
    return [item for index, item in enumerate(result)
            if not (isinstance(item, Ins) and item.op == "GOTO" and _falls_to(result, index, item.args[0]))]


def _skip_over_goto(code: list[Item]) -> list[Item]:
    """IF_X L1; GOTO L2; L1:  ->  IF_notX L2; L1:"""
    result = list(code)
    for index in range(len(result) - 2):
        first, second = result[index], result[index + 1]
        if (isinstance(first, Ins) and first.op in COND_JUMPS and isinstance(second, Ins)
                and second.op == "GOTO" and _falls_to(result, index + 1, first.args[0])):
            result[index] = Ins(FLIP[first.op], second.args, first.span)
            result[index + 1] = Ins("NOP")
    return [item for item in result if not (isinstance(item, Ins) and item.op == "NOP")]


def _fuse(code: list[Item]) -> list[Item]:
    result: list[Item] = []
    for item in code:
        result.append(item)
        if isinstance(item, Ins) and item.op in FUSED_LAST:
            _fuse_tail(result)
    return result


def _fuse_tail(out: list[Item]) -> None:
    """Rewrites the last two or three instructions of ``out`` when a pattern matches."""
    if len(out) < 2:
        return
    a, b = out[-2], out[-1]
    if not (isinstance(a, Ins) and isinstance(b, Ins)):
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
    elif len(out) >= 3 and isinstance(out[-3], Ins) and b.op in MIRROR_CMP:
        _fuse_compare(out)


def _fuse_compare(out: list[Item]) -> None:
    first, second, cmp = out[-3], out[-2], out[-1]
    if first.op in COORD_OPS and second.op in PURE_PUSH and second.op not in COORD_OPS:
        out[-3:] = [second, Ins(f"COORD_{COORD_OPS[first.op]}_{cmp.op}", (), cmp.span)]
    elif second.op in COORD_OPS and first.op in PURE_PUSH and first.op not in COORD_OPS:
        out[-3:] = [first, Ins(f"COORD_{COORD_OPS[second.op]}_{MIRROR_CMP[cmp.op]}", (), cmp.span)]
