"""The verifier held to a target's description (vm.isa.targets): opcodes it runs, its stack depth,
instructions per run on every path, no loop within a run, no PUSH_ARGUMENT in handlers where the
target runs them with argument 0; and the compiler's use of it (E608, the target's slots)."""

from __future__ import annotations

import dataclasses

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from vm.isa.assembler import assemble
from vm.isa.targets import DEFAULT, ORIGINAL
from vm.isa.verifier import verify


def code(text: str) -> bytes:
    return assemble(text)


def test_unimplemented_opcodes_are_refused_only_by_the_target_without_them():
    for name in ("EQUALS_2", "COORD_X", "LESSER", "NEGATE", "CONNECTED_UP_ROLE 1", "ADD"):
        pushes = "PUSH 1\nPUSH 2\n" if name in ("LESSER", "ADD") else "PUSH 1\n" if name in (
            "EQUALS_2", "NEGATE") else ""
        program = code(f"{pushes}{name}\nEND_TERMINATE")
        assert verify(program, target=DEFAULT) == [], name
        errors = verify(program, target=ORIGINAL)
        assert any("not implemented by the original target" in e for e in errors), (name, errors)


def test_stack_depth_is_the_targets():
    five = code("PUSH 1\n" * 5 + "END_TERMINATE")
    six = code("PUSH 1\n" * 6 + "END_TERMINATE")
    assert verify(five, target=ORIGINAL) == [] and verify(six, target=DEFAULT) == []
    assert any("5-entry stack" in e for e in verify(six, target=ORIGINAL))
    # on one path only: the other path stays shallow
    branch = code("SLEEP\nPUSH 1\nIF_FALSE_GOTO deep\nEND_TERMINATE\ndeep:\n"
                  + "PUSH 1\n" * 6 + "END_TERMINATE")
    assert any("5-entry stack" in e for e in verify(branch, target=ORIGINAL))


def test_instructions_per_run_are_counted_on_the_longest_path():
    tight = dataclasses.replace(ORIGINAL, max_steps_per_run=10)
    assert verify(code("NOP\n" * 9 + "END_TERMINATE"), target=tight) == []
    assert any("11 instructions, more than the 10" in e
               for e in verify(code("NOP\n" * 10 + "END_TERMINATE"), target=tight))
    # the longer of two branches counts: 1 + 1 + 9 + 1 = 12 on the long one
    branched = code("PUSH 0\nIF_FALSE_GOTO long\nEND_TERMINATE\nlong:\n" + "NOP\n" * 9 + "END_TERMINATE")
    assert any("12 instructions" in e for e in verify(branched, target=tight))


def test_a_loop_within_one_run_is_refused_by_a_target_a_jump_back_is_not():
    loop = code("top:\nSLEEP\nGOTO top")
    assert verify(loop) == []  # the plain verifier allows it: the VM ends it after 255 steps
    assert any("a loop inside one run" in e for e in verify(loop, target=DEFAULT))
    assert any("a loop inside one run" in e for e in verify(loop, target=ORIGINAL))
    shared_tail = code("PUSH 0\nIF_FALSE_GOTO b\nGOTO tail\ntail:\nSLEEP\nEND_TERMINATE\nb:\nGOTO tail")
    assert verify(shared_tail, target=ORIGINAL) == []


def test_push_argument_in_a_handler_is_refused_where_handlers_get_zero():
    handler = code("HANDLE_EVENT EVENT_PROXIMITY_0 body 5\nEND_TERMINATE\n"
                   "body:\nPUSH_ARGUMENT 0\nSET_LED 1\nEND_TERMINATE")
    command = code("INSTALL_COMMAND 1 USER_0 body 5\nEND_TERMINATE\n"
                   "body:\nPUSH_ARGUMENT 0\nSET_LED 1\nEND_TERMINATE")
    assert verify(handler, target=DEFAULT) == [] and verify(command, target=ORIGINAL) == []
    assert any("PUSH_ARGUMENT in a handler" in e for e in verify(handler, target=ORIGINAL))


@given(st.binary(max_size=80), st.sampled_from([DEFAULT, ORIGINAL]))
def test_the_target_verifier_never_raises(blob, target):
    assert isinstance(verify(blob, target=target), list)


def test_a_fragment_over_the_targets_stack_is_e608_not_an_internal_error():
    deep = "self.x() > " + "(self.y() + " * 16 + "self.y()" + ")" * 16
    result = check_text(f"role A {{ {deep}; }}\ndeployment {{ A }}")
    assert [d.code for d in result.diagnostics] == ["E608"]
    assert "16-entry stack" in result.diagnostics[0].message
    shallow = "self.x() > " + "(self.y() + " * 3 + "self.y()" + ")" * 3
    assert check_text(f"role A {{ {shallow}; }}\ndeployment {{ A }}").diagnostics == []


def test_stored_programs_are_counted_against_the_targets_slots():
    text = ("role A { self.x() > 0;\n  startup s() { "
            + " ".join(f"self.handleEvent(EVENT_PROXIMITY_{k}, "
                       f"{{ self.disableEvent(EVENT_PROXIMITY_{k}); }});" for k in range(4))
            + " } }\ndeployment { A }")
    model = check_text(text).model
    assert "W602" not in [d.code for d in compile_model(model, target=ORIGINAL).diagnostics]
    small = dataclasses.replace(ORIGINAL, program_slots=3)
    found = [d for d in compile_model(model, target=small).diagnostics if d.code == "W602"]
    assert found and "3 slots" in found[0].message
