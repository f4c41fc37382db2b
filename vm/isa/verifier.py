"""The fragment verifier (docs/vm.md): run on every fragment at compile time and on receipt.

Checks: known opcodes, operands present and in range (directions 4..9, events 0..7, commands
1..5 or 128..132, PUSH_ARGUMENT's padding 0); then, walking the control-flow graph from offset 0:
jump targets inside the fragment and on instruction boundaries of the linear decoding, control
never falling off the end, operand stack within 0..16 on every path (abstract interpretation
tracking the set of possible depths at each instruction), HANDLE_EVENT / INSTALL_COMMAND ranges
non-empty, inside the fragment and on boundaries, and the embedded code verified as a fragment of
its own (its jump targets are offsets from its own start, as it is stored and run alone; its
instructions are therefore not target-checked as part of the enclosing code). ``strict=True``
refuses this project's extension opcodes. Returns error strings; never raises.
"""

from __future__ import annotations

from dataclasses import dataclass

from vm.isa.disassembler import PUSH_SMALL, Decoded, disassemble, successors
from vm.isa.opcodes import (
    BY_OPCODE,
    COMMANDS,
    MAX_STACK,
    PUSH_SMALL_BASE,
    SLOT_BYTES,
    STATE_SLOTS,
    USER_COMMAND_BASE,
    WHERE_ALL,
    WHERE_CHILDREN,
    WHERE_CONNECTOR,
    Operand,
)
from vm.isa.targets import Target
from vm.navigation import DIRECTIONS

MAX_FRAGMENT = SLOT_BYTES


@dataclass(frozen=True, slots=True)
class _Rules:
    strict: bool
    max_size: int
    max_stack: int = MAX_STACK
    target: Target | None = None
    handler: bool = False  # the code is a handler (HANDLE_EVENT's range)


def verify(code: bytes, *, strict: bool = False, max_size: int = MAX_FRAGMENT,
           target: Target | None = None, max_stack: int = MAX_STACK) -> list[str]:
    """Errors of a fragment ([] when it is well formed). ``max_stack`` applies without a target
    (the compiler raises it to tell a malformed fragment from one over a target's limits)."""
    if isinstance(code, int):  # bytes(n) would make n zero bytes
        return [f"not a fragment: {type(code).__name__}"]
    try:
        code = bytes(code)
    except (TypeError, ValueError) as error:
        return [f"not a fragment: {error}"]
    rules = _Rules(strict, max_size, max_stack)
    if target is not None:
        rules = _Rules(strict, min(max_size, target.slot_bytes), target.max_stack, target)
    return _verify(code, rules, depth=0)


def _data_unreachable(decoded: list[Decoded]) -> list[str]:
    """Control never reaches the DATA that ends a fragment: nothing falls into it or jumps to it."""
    if not decoded or decoded[-1].name != "DATA":
        return []
    data = decoded[-1].offset
    before = decoded[-2] if len(decoded) > 1 else None
    if before is None or before.info is None or not before.info.no_fallthrough or before.name == "DATA":
        return [f"offset {data}: control falls into DATA, the value the program carries"]
    for d in decoded:
        if d.info is not None and Operand.TARGET in d.info.operands and \
                d.operands[d.info.operands.index(Operand.TARGET)] == data:
            return [f"offset {d.offset}: {d.name} jumps to DATA, the value the program carries"]
    return []


def _verify(code: bytes, rules: _Rules, depth: int) -> list[str]:
    if not code:
        return ["empty fragment"]
    if len(code) > rules.max_size:
        return [f"fragment of {len(code)} bytes exceeds the {rules.max_size}-byte program slot"]
    decoded = disassemble(code)
    errors: list[str] = []
    for d in decoded:
        errors.extend(_check_instruction(d, code, rules))
        if d.name == "DATA" and d.offset != len(code) - 2:
            errors.append(f"offset {d.offset}: DATA (the value a program carries) must end the fragment")
    errors.extend(_data_unreachable(decoded))
    if errors:
        return errors
    at = {d.offset: d for d in decoded}
    errors = _check_flow(code, at, rules, depth)
    if not errors and rules.target is not None:
        errors = _check_steps(code, at, rules.target)
    return errors


def _check_target(d: Decoded, rules: _Rules) -> list[str]:
    target = rules.target
    if target is None or d.info is None:
        return []
    where = f"offset {d.offset}"
    if not target.implements(d.opcode):
        return [f"{where}: {d.name} is not implemented by the {target.name} target"]
    if rules.handler and d.name == "PUSH_ARGUMENT" and target.quirks.handler_refires_with_zero:
        return [f"{where}: PUSH_ARGUMENT in a handler: the {target.name} target runs handlers with "
                "argument 0"]
    return []


def _check_instruction(d: Decoded, code: bytes, rules: _Rules) -> list[str]:
    strict = rules.strict
    where = f"offset {d.offset}"
    if d.raw:
        if d.opcode in BY_OPCODE:
            return [f"{where}: {BY_OPCODE[d.opcode].name} is missing operands at the end of the fragment"]
        return [f"{where}: unknown opcode {d.opcode}"]
    if d.info is None:
        return []
    errors: list[str] = _check_target(d, rules)
    if strict and d.info.ext:
        errors.append(f"{where}: {d.name} is an extension opcode, refused under strict ISA")
    for kind, value in zip(d.info.operands, d.operands, strict=True):
        if kind is Operand.DIR and value not in DIRECTIONS:
            errors.append(f"{where}: {d.name}: direction {value} is not one of 4..9")
        elif kind is Operand.EVENT and value > 7:
            errors.append(f"{where}: {d.name}: event {value} is not one of 0..7")
        elif kind is Operand.COMMAND and value not in COMMANDS:
            errors.append(f"{where}: {d.name}: command {value} is not 1..5 or 128..132")
        elif kind is Operand.ZERO and value != 0:
            errors.append(f"{where}: {d.name}: operand must be 0, got {value}")
        elif kind is Operand.STATE and value >= STATE_SLOTS:
            errors.append(f"{where}: {d.name}: state {value} is not one of 0..{STATE_SLOTS - 1}")
        elif kind is Operand.GATHER and (value & 0xC8):
            errors.append(f"{where}: {d.name}: {value} is not an aggregate (0..3) and a published "
                          "state (0..7)")
        elif kind is Operand.WHERE and not (value in (WHERE_ALL, WHERE_CHILDREN) or value in DIRECTIONS
                                            or WHERE_CONNECTOR <= value < WHERE_CONNECTOR + 8):
            errors.append(f"{where}: {d.name}: {value} names no neighbours (0, 1, 4..9 or 16..23)")
    if d.name == "INSTALL_COMMAND" and d.operands[1] < USER_COMMAND_BASE:
        errors.append(f"{where}: INSTALL_COMMAND: command {d.operands[1]} is not a user command (>= 128)")
    return errors


def _check_targets(d: Decoded, code: bytes, at: dict[int, Decoded], rules: _Rules,
                   depth: int) -> list[str]:
    if d.info is None:
        return []
    where = f"offset {d.offset}: {d.name}"
    errors: list[str] = []
    ops = dict(zip(d.info.operands, d.operands, strict=True))
    if Operand.TARGET in ops:
        t = ops[Operand.TARGET]
        if t >= len(code):
            errors.append(f"{where}: jump target {t} is outside the {len(code)}-byte fragment")
        elif t not in at:
            errors.append(f"{where}: jump target {t} is not on an instruction boundary")
    if d.name == "TABLE":  # data, not code: values 0..127 stored as bytes >= 128, never run
        start, size = ops[Operand.START], ops[Operand.SIZE]
        table = code[start:start + size]
        if size == 0 or start + size > len(code):
            errors.append(f"{where}: table [{start}, {start + size}) is empty or outside the "
                          f"{len(code)}-byte fragment")
        elif any(b < PUSH_SMALL_BASE for b in table):
            errors.append(f"{where}: table [{start}, {start + size}) holds a byte < "
                          f"{PUSH_SMALL_BASE} (its values are 0..127, stored + {PUSH_SMALL_BASE})")
        return errors
    if Operand.START in ops:
        start, size = ops[Operand.START], ops[Operand.SIZE]
        end = start + size
        if size == 0:
            errors.append(f"{where}: empty code range at {start}")
        elif end > len(code):
            errors.append(f"{where}: code range [{start}, {end}) is outside the {len(code)}-byte fragment")
        elif start not in at or (end not in at and end != len(code)):
            errors.append(f"{where}: code range [{start}, {end}) is not on instruction boundaries")
        elif (start, end) != (0, len(code)) and depth < 8:
            inner = _Rules(rules.strict, rules.max_size, rules.max_stack, rules.target,
                           handler=d.name == "HANDLE_EVENT")
            for e in _verify(code[start:end], inner, depth + 1):
                errors.append(f"{where}: embedded code [{start}, {end}): {e}")
    return errors


def _check_flow(code: bytes, at: dict[int, Decoded], rules: _Rules, depth: int) -> list[str]:
    """Walk the control-flow graph from offset 0 with the set of stack depths at each instruction.
    Targets and code ranges are checked only where the instruction runs as part of this code:
    an embedded handler's instructions are checked when the handler is verified on its own."""
    seen: dict[int, set[int]] = {}
    broken: set[int] = set()  # instructions with bad targets or ranges: not followed
    work: list[tuple[int, int]] = [(0, 0)]
    errors: list[str] = []
    while work:
        pc, stack = work.pop()
        if pc not in seen:
            seen[pc] = set()
            problems = _check_targets(at[pc], code, at, rules, depth)
            errors.extend(problems)
            if problems:
                broken.add(pc)
        if pc in broken or stack in seen[pc]:
            continue
        seen[pc].add(stack)
        d = at[pc]
        pops, pushes = (0, 1) if d.name == PUSH_SMALL else (d.info.pops, d.info.pushes) if d.info else (0, 0)
        if stack < pops:
            errors.append(f"offset {pc}: {d.name} pops {pops} value(s) from a stack of {stack}")
            continue
        after = stack - pops + pushes
        if after > rules.max_stack:
            errors.append(f"offset {pc}: {d.name} overflows the {rules.max_stack}-entry stack")
            continue
        for nxt in successors(d):
            if nxt >= len(code):
                errors.append(f"offset {pc}: control falls off the end of the fragment after {d.name}")
            else:
                work.append((nxt, after))
    return sorted(set(errors), key=lambda e: int(e.split(":")[0].split()[1]))




def _check_steps(code: bytes, at: dict[int, Decoded], target: Target) -> list[str]:
    """The most instructions one run executes, over every path from offset 0 (the flow is already
    known to be well formed). A cycle could repeat without bound: refused."""
    longest: dict[int, int] = {}
    on_path: set[int] = set()
    # iterative depth-first search: (pc, successors still to visit)
    stack: list[tuple[int, list[int]]] = [(0, list(successors(at[0])))]
    on_path.add(0)
    while stack:
        pc, pending = stack[-1]
        if pending:
            nxt = pending.pop()
            if nxt in on_path:
                return [f"offset {at[pc].offset}: {at[pc].name} jumps back to offset {nxt}: a loop "
                        f"inside one run, which the {target.name} target ends after "
                        f"{target.max_steps_per_run} instructions"]
            if nxt not in longest:
                on_path.add(nxt)
                stack.append((nxt, list(successors(at[nxt]))))
            continue
        stack.pop()
        on_path.discard(pc)
        longest[pc] = 1 + max((longest[n] for n in successors(at[pc])), default=0)
    if longest[0] > target.max_steps_per_run:
        return [f"offset 0: a run may execute {longest[0]} instructions, more than the "
                f"{target.max_steps_per_run} of the {target.name} target"]
    return []
