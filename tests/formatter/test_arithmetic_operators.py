"""Issue 25: the formatter, the parser's precedence and the disassembly (the listing and the
debugger's view) know * / %; '//' and '/*' stay comments next to a division."""

from __future__ import annotations

from rdcd_core.formatter import format_text
from rdcd_core.frontend import check_text
from rdcd_core.syntax import ast
from rdcd_core.syntax.parser import parse
from vm.isa.assembler import assemble
from vm.isa.disassembler import decode_at, disassemble, to_text

SOURCE = ("state p:=0;\nrole R{behavior b(){p:=(p+1)%4*2/ -1;// c / d\n/* x */self.setLed(p*3);"
          "self.turnTowards(p/1*30);}}\ndeployment{R}\n")


def test_formatting_keeps_the_operators_and_is_stable() -> None:
    once = format_text(SOURCE)
    assert once is not None and "p := (p + 1) % 4 * 2 / -1;" in once and "self.setLed(p * 3);" in once
    assert "// c / d" in once and "/* x */" in once
    assert format_text(once) == once
    assert not check_text(once).has_errors


def test_multiplicative_operators_bind_tighter_than_additive_and_associate_left() -> None:
    program = parse("role R { 1 + 2 * 3 - 8 / 2 % 3 > 0; }\ndeployment { R }\n").program
    invariant = program.roles[0].members[0].expr
    additive = invariant.left
    assert additive.op == "-" and additive.left.op == "+" and additive.left.right.op == "*"
    modulo = additive.right
    assert modulo.op == "%" and modulo.left.op == "/"
    assert isinstance(modulo.right, ast.IntLit)


def test_the_disassembly_names_the_new_instructions() -> None:
    names = ("TURN_STACK", "TURN_TO_STACK", "TURN_BY_STACK", "SLEEP_ROTATIONS_STACK", "MUL", "DIV", "MOD")
    code = assemble("\n".join(f"PUSH 1\nPUSH 1\n{name}" for name in names) + "\nEND_TERMINATE")
    assert [d.name for d in disassemble(code) if d.name != "PUSH"] == [*names, "END_TERMINATE"]
    assert decode_at(code, 2).name == "TURN_STACK"  # what the debugger's disassembly view reads
    assert all(name in to_text(code) for name in names)
