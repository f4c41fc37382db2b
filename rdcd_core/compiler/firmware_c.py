"""The C form for the ATRON firmware (docs/vm.md, "Loading" and "The C interface of that file").

The firmware reads no program at run time: its ``actions.c`` includes a generated file that
defines the fragments as ``unsigned char NAME[SIZE+1]`` arrays, ``static void dcd_action(...)``,
which runs on the entry module and sends each fragment in turn on channels 0-7, and the role
table as ``check_role_instanceof`` (the firmware's ``roles.c``, hard-coded for the paper's car,
is left out of the build). The environment parameter is written with the firmware's macros
``USSRONLY``/``USSRONLYC`` so that one file builds for the simulator and for the modules.

Spacing: each fragment is sent ``INJECTION_DELAY_MS`` after the previous one (and the first after
the structure has started), the rhythm of the authors' generated files. The compiler's fragments
need only their order: a discovery fragment that reads neighbour roles, and every continuation
fragment, starts with SLEEP on each module, so the roles announced by the fragments before it have
arrived; the delay lets each fragment diffuse through the structure before the next one is sent.
"""

from __future__ import annotations

from rdcd_core.compiler.program import CompiledProgram, Fragment
from rdcd_core.compiler.render import c_comment_text, c_name, instruction_text, regions
from vm.isa.disassembler import PUSH_SMALL, disassemble

INJECTION_DELAY_MS = 8000
ROLE_ANY = 255  # the firmware's roles.h: "any role" (vm/roles.py uses the same)


def render_firmware(program: CompiledProgram, source: str = "") -> str:
    names = {r.id: r.name for r in program.roles}
    out = _preamble(program, source)
    for fragment in program.fragments:
        out += _array(fragment, names)
    out += _role_table(program)
    out += _dcd_action(program)
    return "\n".join(out) + "\n"


def _preamble(program: CompiledProgram, source: str) -> list[str]:
    order = " -> ".join(program.injection) or "(none)"
    top = max((r.id for r in program.roles), default=0)
    return [
        f"/* DCD-VM program for the ATRON firmware (rdcd target {program.target}), compiled by rdcd",
        f" * from {c_comment_text(source or 'an RDCD program')} .",
        " * Include it from the firmware's actions.c and leave roles.c out of the build:",
        " * check_role_instanceof below is this program's role table. dcd_action runs on the entry",
        " * module; it sends the fragments to its neighbours (it does not run them itself) in this",
        f" * order, {INJECTION_DELAY_MS // 1000} s apart: {c_comment_text(order)} .",
        f" * {len(program.fragments)} fragments, {program.total_bytes} bytes, largest "
        f"{program.max_fragment_bytes} . */",
        "#include <stdint.h>",
        "",
        f"#if defined(MAX_N_ROLES) && MAX_N_ROLES < {top + 1}",
        f"#error \"this program uses role ids up to {top}: MAX_N_ROLES in roles.h must be at least "
        f"{top + 1}\"",
        "#endif",
        "",
    ]


def _array(fragment: Fragment, roles: dict[int, str]) -> list[str]:
    name = c_name(fragment.name)
    size = f"SIZE_{name}"
    lines = [f"/* {c_comment_text(fragment.name)}: {fragment.kind}, {fragment.size} bytes . */",
             f"#define {size} {fragment.size}",
             f"unsigned char {name}[{size} + 1] = {{"]
    found = regions(fragment.code)
    for d in disassemble(fragment.code):
        length = 1 if d.name == PUSH_SMALL or d.info is None else d.size
        data = ", ".join(str(b) for b in fragment.code[d.offset:d.offset + length])
        base = max((start for start, end in found if start <= d.offset < end), default=0)
        text = c_comment_text(instruction_text(d, roles, base))
        lines.append(f"    /* {d.offset:2d} */ {data + ',':<16} /* {text} */")
    lines += ["    0 /* the end mark of the authors' arrays, not sent */", "};", ""]
    return lines


def _role_table(program: CompiledProgram) -> list[str]:
    lines = ["/* The role table (instance-of); 255 is any role. */"]
    lines += [f"/* {r.id:2d} {c_comment_text(r.name)} ({r.kind}) */" for r in program.roles]
    lines += ["uint8_t check_role_instanceof(uint8_t self_role, uint8_t test_role) {",
              f"    if (test_role == {ROLE_ANY} || self_role == test_role) return 1;",
              "    switch (self_role) {"]
    for role in program.roles:
        others = [i for i in role.instance_of if i != role.id]
        if others:
            test = " || ".join(f"test_role == {i}" for i in others)
            lines.append(f"    case {role.id}: return {test};")
    lines += ["    default: return 0;", "    }", "}", ""]
    return lines


def _dcd_action(program: CompiledProgram) -> list[str]:
    lines = ["static void dcd_action(USSRONLY(USSREnv *env)) {"]
    if program.injection:
        lines += ["    InterpreterContext context = {0, 0, 0, ARG_NORTH_SOUTH, 0, 0, 0};",
                  "    uint8_t channel;"]
    for step, fragment_name in enumerate(program.injection, 1):
        name = c_name(fragment_name)
        lines += [f"    /* {step}. {c_comment_text(fragment_name)} */",
                  f"    delay(USSRONLYC(env) {INJECTION_DELAY_MS});",
                  "    for (channel = 0; channel < 8; channel++)",
                  f"        sendProgramMaybe(USSRONLYC(env) &context, channel, {name}, SIZE_{name});",
                  "    context.program_id++;"]
    if not program.injection:
        lines.append("    /* no fragments to send */")
    lines += ["}", ""]
    return lines

