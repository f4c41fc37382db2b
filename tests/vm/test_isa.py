"""Assembler, disassembler and verifier (docs/vm.md)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vm.isa.assembler import AssemblyError, assemble
from vm.isa.disassembler import disassemble, to_text
from vm.isa.opcodes import BY_NAME, INSTRUCTIONS
from vm.isa.verifier import verify


def test_assemble_forms_and_names() -> None:
    code = assemble("""
    start:  CONNECTED_DIR UP        ; a comment
            PUSH 3
            PUSH 200                # not a one-byte constant
            PUSH -1
            IF_FALSE_GOTO done
            HANDLE_EVENT EVENT_PROXIMITY_1, handler, handler_end-handler
            SEND_COMMAND ANY ROTATE_CW -1
    done:   END_TERMINATE
    handler: EVAL_COMMAND STOP 0
            END_TERMINATE
    handler_end:
    """)
    assert list(code) == [11, 8, 131, 54, 200, 54, 255, 15, 17, 30, 1, 18, 4, 31, 255, 1, 255, 13,
                          33, 3, 0, 13]
    assert verify(code) == []


def test_assembler_errors_name_the_line() -> None:
    with pytest.raises(AssemblyError, match="line 2"):
        assemble("NOP\nFLY 3\n")
    with pytest.raises(AssemblyError, match="takes 1 operand"):
        assemble("GOTO\n")
    with pytest.raises(AssemblyError, match="unknown name"):
        assemble("GOTO nowhere\n")
    with pytest.raises(AssemblyError, match="does not fit"):
        assemble("PUSHC 300\n")
    with pytest.raises(AssemblyError, match="twice"):
        assemble("a: NOP\na: NOP\n")


@pytest.mark.parametrize("other_break", ["\f", "\v", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029"])
@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_assembler_lines_are_the_lsp_lines(other_break: str, newline: str) -> None:
    """Only \\r\\n, \\r and \\n end a line (the project's one definition, the LSP's): a form feed
    or U+2028 in a comment stays in the comment, and errors name the line an editor shows."""
    text = f"NOP ; a comment{other_break}GOTO nowhere{newline}NOP{newline}"
    assert assemble(text) == assemble("NOP\nNOP\n")
    with pytest.raises(AssemblyError, match="line 3"):
        assemble(f"NOP ; x{other_break}y{newline}NOP{newline}FLY 3{newline}")


def test_every_instruction_assembles_to_its_size() -> None:
    for ins in INSTRUCTIONS:
        operands = " ".join("4" if k == "dir" else "0" if k == "zero" else "1" for k in ins.operands)
        code = assemble(f"{ins.name} {operands}")
        assert len(code) == ins.size and code[0] == ins.opcode
        [d] = disassemble(code)
        assert d.name == ins.name


@given(st.binary(max_size=80))
def test_disassemble_then_assemble_is_identity(code: bytes) -> None:
    assert assemble(to_text(code)) == code
    assert assemble(to_text(code, with_offsets=True)) == code


@given(st.binary(max_size=80), st.booleans())
def test_verifier_never_raises(code: bytes, strict: bool) -> None:
    errors = verify(code, strict=strict)
    assert isinstance(errors, list) and all(isinstance(e, str) for e in errors)


ACCEPT = [
    "END_TERMINATE",
    "PUSH 1\nIF_FALSE_GOTO e\nNOP\ne: END_REPEAT",
    "loop: SLEEP\nGOTO loop",
    "CONNECTED_SIZEOF\nEQUALS_1\nIF_TRUE_GOTO a\nMIGRATE_CONTINUE\na: END_TERMINATE",
    "INSTALL_COMMAND 3 USER_0 c e-c\nEND_TERMINATE\nc: PUSH_ARGUMENT 0\nEVAL_COMMAND_STACK_ARG ROTATE_TO\n"
    "END_TERMINATE\ne:",
    "HANDLE_EVENT 2 h e-h\nEND_TERMINATE\nh: PUSH 0\nIF_FALSE_GOTO 0\nEND_TERMINATE\ne:",  # relative to h
    "\n".join(["PUSH 1"] * 16) + "\nEND_TERMINATE",
]


@pytest.mark.parametrize("text", ACCEPT)
def test_verifier_accepts(text: str) -> None:
    assert verify(assemble(text)) == []


REJECT = [
    (b"", "empty"),
    (bytes([0]), "unknown opcode 0"),
    (bytes([126, 13]), "unknown opcode 126"),
    (bytes([16]), "missing operands"),
    (bytes([16, 9]), "outside"),
    (bytes([54, 1, 16, 1]), "not on an instruction boundary"),
    (bytes([127]), "falls off the end"),
    (bytes([6, 13]), "pops 1"),
    (bytes([128] * 17 + [13]), "overflows"),
    (assemble("l: PUSH 1\nGOTO l"), "overflows"),
    (bytes([11, 3, 13]), "direction 3"),
    (bytes([32, 8, 13]), "event 8"),
    (bytes([33, 6, 0, 13]), "command 6"),
    (bytes([53, 1, 13]), "must be 0"),
    (bytes([30, 0, 2, 9, 13]), "outside"),
    (bytes([30, 0, 4, 0, 13]), "empty code range"),
    (bytes([30, 0, 3, 1, 13, 54, 13]), "boundaries"),
    (assemble("HANDLE_EVENT 1 h e-h\nEND_TERMINATE\nh: NOP\ne:"), "embedded code"),
    (assemble("INSTALL_COMMAND 1 3 c e-c\nEND_TERMINATE\nc: END_TERMINATE\ne:"), "not a user command"),
    (bytes([13] * 65), "64-byte"),
]


@pytest.mark.parametrize(("code", "message"), REJECT)
def test_verifier_rejects(code: bytes, message: str) -> None:
    errors = verify(code)
    assert errors and any(message in e for e in errors), errors


def test_strict_refuses_extensions() -> None:
    code = assemble("PUSH 1\nPUSH 2\nADD\nEND_TERMINATE")
    assert verify(code) == []
    assert any("extension" in e for e in verify(code, strict=True))
    assert BY_NAME["ADD"].ext and not BY_NAME["GOTO"].ext


def test_nested_embedded_code_is_verified() -> None:
    # the inner handler's range is relative to the outer handler's own start
    good = assemble("HANDLE_EVENT 0 h e-h\nEND_TERMINATE\nh: HANDLE_EVENT 1 5 1\nEND_TERMINATE\n"
                    "END_REPEAT\ne:")
    assert verify(good) == []
    bad = assemble("HANDLE_EVENT 0 h e-h\nEND_TERMINATE\nh: HANDLE_EVENT 1 4 2\nEND_TERMINATE\ne:")
    assert any("embedded code" in e for e in verify(bad))


def test_listing_labels_only_targets_of_reachable_code() -> None:
    from vm.isa.disassembler import reachable
    code = assemble("HANDLE_EVENT 2 h e-h\nGOTO x\nx: END_TERMINATE\nh: PUSH 0\nIF_FALSE_GOTO 0\n"
                    "END_TERMINATE\ne:")
    assert reachable(code) == {0, 4, 6}
    text = to_text(code)
    assert "GOTO L6" in text and "IF_FALSE_GOTO 0" in text and "L0:" not in text
