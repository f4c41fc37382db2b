"""TABLE (issue 24): a constant table read by index, its bytes (values + 128) after the fragment's
last instruction; pop i, push the i-th value, 0 outside the table. An extension: the original
firmware does not have it."""

from __future__ import annotations

import pytest
from vm_fakes import FakeHal

from vm.isa.assembler import assemble
from vm.isa.disassembler import to_text
from vm.isa.opcodes import BY_NAME
from vm.isa.targets import ORIGINAL
from vm.isa.verifier import verify
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime

ROLES = RoleTable({1: "A"}, {})


def program(index: int) -> bytes:
    """Show the value at ``index`` of the table 5, 0, 9 on the LED."""
    return assemble(f"""
        PUSHC {index}
        TABLE t e-t
        SET_LED_STACK
        END_TERMINATE
    t:  .byte 133 128 137
    e:
    """)


def led(code: bytes) -> tuple[int, list]:
    vm = ModuleRuntime(FakeHal(connected={0}), ROLES, module_id=1)
    vm.inject(code)
    vm.step()
    return vm.led, vm.errors


@pytest.mark.parametrize(("index", "value"), [(0, 5), (1, 0), (2, 9), (3, 0), (-1, 0), (127, 0),
                                              (-128, 0)])
def test_the_value_at_the_index_and_zero_outside(index: int, value: int) -> None:
    code = program(index)
    assert verify(code) == []
    assert led(code) == (value, [])


def test_the_table_is_in_the_table_of_instructions() -> None:
    ins = BY_NAME["TABLE"]
    assert (ins.opcode, ins.pops, ins.pushes, ins.ext, ins.size) == (80, 1, 1, True, 3)


def test_the_disassembler_shows_the_table_bytes_as_pushes_never_reached() -> None:
    text = to_text(program(0))
    assert "TABLE" in text and "END_TERMINATE" in text


def test_the_verifier_refuses_a_table_outside_the_fragment_or_with_code_bytes() -> None:
    outside = assemble("PUSH 0\nTABLE 5 9\nSET_LED_STACK\nEND_TERMINATE")
    assert any("outside" in e for e in verify(outside))
    empty = assemble("PUSH 0\nTABLE 5 0\nSET_LED_STACK\nEND_TERMINATE\nt: .byte 130")
    assert any("empty" in e for e in verify(empty))
    low = assemble("PUSH 0\nTABLE t e-t\nSET_LED_STACK\nEND_TERMINATE\nt: .byte 130 127\ne:")
    assert any("holds a byte" in e for e in verify(low))


def test_the_original_firmware_has_no_table() -> None:
    errors = verify(program(0), target=ORIGINAL)
    assert errors and any("TABLE" in e for e in errors)
