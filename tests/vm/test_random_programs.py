"""Random well-formed fragments (built from the instruction table, then verified) run safely in a
small world: no internal errors, no program accepted twice by a module."""

from __future__ import annotations

import random

from hypothesis import given, settings
from hypothesis import strategies as st
from vm_fakes import World, random_structure

from vm.isa.opcodes import INSTRUCTIONS, Operand
from vm.isa.verifier import verify
from vm.roles import RoleTable

ROLES = RoleTable({1: "A", 2: "B"}, {2: frozenset({1})})
STRAIGHT = [i for i in INSTRUCTIONS if Operand.TARGET not in i.operands and Operand.START not in i.operands
            and not i.no_fallthrough and i.name not in ("SLEEP", "SLEEP_ROTATIONS")]
ENDINGS = [bytes([13]), bytes([14]), bytes([18])]
OPERAND = {Operand.DIR: st.integers(4, 9), Operand.ROLE: st.sampled_from([0, 1, 2, 255]),
           Operand.EVENT: st.integers(0, 7), Operand.COMMAND: st.sampled_from([1, 2, 3, 4, 5, 128, 129]),
           Operand.BYTE: st.integers(0, 255), Operand.ZERO: st.just(0),
           Operand.STATE: st.integers(0, 31), Operand.GATHER: st.sampled_from([0, 7, 0x13, 0x21, 0x37]),
           Operand.WHERE: st.sampled_from([0, 1, 4, 9, 16, 23])}


@st.composite
def fragments(draw: st.DrawFn) -> bytes:
    code = bytearray()
    depth = 0
    for _ in range(draw(st.integers(0, 12))):
        if depth == 0 or draw(st.booleans()) and depth < 14:
            code.append(128 + draw(st.integers(0, 127)))
            depth += 1
            continue
        ins = draw(st.sampled_from([i for i in STRAIGHT if i.pops <= depth]))
        code.append(ins.opcode)
        code.extend(draw(OPERAND[k]) for k in ins.operands)
        depth += ins.pushes - ins.pops
    code.extend(draw(st.sampled_from(ENDINGS)))
    return bytes(code)


@settings(max_examples=40, deadline=None)
@given(fragments(), st.integers(0, 1000))
def test_random_valid_fragments_run_safely(code: bytes, seed: int) -> None:
    assert verify(code) == [], code
    world = World(random_structure(6, random.Random(seed)), ROLES, loss=0.1, seed=seed)
    world.vms[0].inject(code)
    world.run(1.5)
    for vm in world.vms:
        assert not any("internal error" in m for _, m in vm.errors)
        assert sum(1 for _, k, _ in vm.event_log if k == "program") <= 1
