"""Output formats of ``rdcd compile``: listing, JSON and C."""

from __future__ import annotations

import json
import re

from rdcd_core.compiler.geometry import DIRECTION_NAMES
from rdcd_core.compiler.program import HEADER_BYTES, CompiledProgram, Fragment
from vm.isa.disassembler import PUSH_SMALL, Decoded, disassemble
from vm.isa.opcodes import BUILTIN_COMMANDS, USER_COMMAND_BASE, Operand
from vm.isa.targets import DEFAULT, TARGETS


def to_json(program: CompiledProgram) -> dict[str, object]:
    data = _json_core(program)
    if program.states:  # the state memory's layout (programs with state only)
        data["states"] = [{"name": s.name, "index": s.index, "initial": s.initial, "role": s.owner,
                           "published": s.published} for s in program.states]
    return data


def _json_core(program: CompiledProgram) -> dict[str, object]:
    return {
        "target": program.target,
        "packet_budget": program.packet_budget,
        "total_bytes": program.total_bytes,
        "max_fragment_bytes": program.max_fragment_bytes,
        "fragments": [{"name": f.name, "kind": f.kind, "role": f.role, "size": f.size,
                       "bytes": list(f.code), "source": {"line": f.source[0], "end_line": f.source[1]}}
                      for f in program.fragments],
        "roles": [{"id": r.id, "name": r.name, "kind": r.kind, "instance_of": list(r.instance_of)}
                  for r in program.roles],
        "injection": list(program.injection),
    }


def render_json(program: CompiledProgram) -> str:
    return json.dumps(to_json(program), indent=2)


def regions(code: bytes) -> list[tuple[int, int]]:
    """(start, end) of every embedded body, absolute offsets, in order of discovery."""
    found: list[tuple[int, int]] = []
    for d in disassemble(code):
        if d.info is None or Operand.START not in d.info.operands:
            continue
        ops = dict(zip(d.info.operands, d.operands, strict=True))
        base = base_of(found, d.offset)
        region = (base + ops[Operand.START], base + ops[Operand.START] + ops[Operand.SIZE])
        if region not in found:
            found.append(region)
    return found


def base_of(found: list[tuple[int, int]], offset: int) -> int:
    inside = [start for start, end in found if start <= offset < end]
    return max(inside, default=0)


def operand_text(kind: Operand, value: int, roles: dict[int, str], base: int) -> str:
    if kind is Operand.ROLE:
        return roles.get(value, str(value))
    if kind is Operand.DIR:
        return DIRECTION_NAMES.get(value, str(value))
    if kind is Operand.EVENT:
        return f"EVENT_PROXIMITY_{value}"
    if kind is Operand.COMMAND:
        if value >= USER_COMMAND_BASE:
            return f"USER_{value - USER_COMMAND_BASE}"
        return BUILTIN_COMMANDS.get(value, str(value))
    if kind is Operand.TARGET:
        return f"L{base + value}"
    if kind is Operand.START:
        return f"@{base + value}"
    if kind is Operand.BYTE:
        return str(value - 256 if value > 127 else value)
    return str(value)


def instruction_text(d: Decoded, roles: dict[int, str], base: int) -> str:
    if d.name == PUSH_SMALL:
        return f"PUSH {d.operands[0]}"
    if d.info is None:
        return f".byte {d.operands[0]}"
    ops = [operand_text(k, v, roles, base) for k, v in zip(d.info.operands, d.operands, strict=True)]
    return " ".join([d.name, *ops])


def render_fragment(fragment: Fragment, program: CompiledProgram) -> list[str]:
    roles = {r.id: r.name for r in program.roles}
    budget = program.program_budget
    lines = [f"fragment {fragment.name}  kind={fragment.kind} role={fragment.role or '-'}  "
             f"{fragment.size}/{budget} program bytes, packet {fragment.size + HEADER_BYTES}/"
             f"{program.packet_budget}" + ("  OVER BUDGET" if fragment.size > budget else "")]
    found = regions(fragment.code)
    sources = {entry.offset: entry.line for entry in fragment.source_map}
    targets = _targets(fragment.code, found)
    for d in disassemble(fragment.code):
        for start, end in found:
            if d.offset == start:
                lines.append(f"    ; embedded body [{start}, {end})")
        if d.offset in targets:
            lines.append(f"  L{d.offset}:")
        size = 1 if d.name == PUSH_SMALL or d.info is None else d.size
        raw = " ".join(f"{b:02x}" for b in fragment.code[d.offset:d.offset + size])
        text = instruction_text(d, roles, base_of(found, d.offset))
        line = sources.get(d.offset, 0)
        where = f"; line {line}" if line else ""
        lines.append(f"  {d.offset:3d}  {raw:<15} {text:<40} {where}".rstrip())
    return lines


def _targets(code: bytes, found: list[tuple[int, int]]) -> set[int]:
    result: set[int] = set()
    for d in disassemble(code):
        if d.info is not None and Operand.TARGET in d.info.operands:
            result.add(base_of(found, d.offset) + d.operands[d.info.operands.index(Operand.TARGET)])
    return result


def render_listing(program: CompiledProgram) -> str:
    lines: list[str] = []
    for fragment in program.fragments:
        lines += render_fragment(fragment, program) + [""]
    lines.append("roles:")
    names = {r.id: r.name for r in program.roles}
    for role in program.roles:
        parents = ", ".join(names[i] for i in role.instance_of if i != role.id)
        lines.append(f"  {role.id:2d} {role.name:<28} {role.kind:<12} instance of: {parents or '-'}")
    if program.states:
        lines.append("states:")
        for state in program.states:
            kind = f"role state of {state.owner}" if state.owner else "module state"
            lines.append(f"  {state.index:3d} {state.name:<26} {kind}, initial {state.initial}"
                         + (", published" if state.published else ""))
    lines.append("injection: " + " -> ".join(program.injection))
    lines.append(f"total {program.total_bytes} bytes in {len(program.fragments)} fragments, "
                 f"largest {program.max_fragment_bytes} (budget {program.program_budget})")
    return "\n".join(lines) + "\n"


def c_name(name: str) -> str:
    return "rdcd_" + re.sub(r"\W", "_", name)


def c_comment_text(text: str) -> str:
    """``text`` made safe inside a C block comment: no ``*/`` ends it early, no line breaks or
    other control characters split it (a file name may hold any of these)."""
    text = "".join(c if c.isprintable() else "?" for c in text)
    return text.replace("*/", "*\\/").replace("/*", "/\\*")


def render_c(program: CompiledProgram, source: str = "") -> str:
    """The C form: for a target that builds the program into its firmware (``loads_c_file``), the
    file the firmware includes (``render_firmware``); otherwise the fragments, the injection
    sequence and the role table as plain C data."""
    if TARGETS.get(program.target, DEFAULT).loads_c_file:
        from rdcd_core.compiler.firmware_c import render_firmware

        return render_firmware(program, source)
    out = [f"/* DCD-VM fragments compiled by rdcd from {c_comment_text(source or 'an RDCD program')}. */",
           "#include <stdint.h>", ""]
    for f in program.fragments:
        data = ", ".join(str(b) for b in f.code)
        out.append(f"/* {f.name}: {f.kind}, {f.size} bytes */")
        out.append(f"const uint8_t {c_name(f.name)}[{f.size}] = {{ {data} }};")
    out += ["", "/* Injection sequence: inject in this order at the entry module. */",
            f"#define RDCD_INJECTION_COUNT {len(program.injection)}",
            "const uint8_t *const rdcd_injection[RDCD_INJECTION_COUNT] = {",
            *[f"    {c_name(n)}," for n in program.injection], "};",
            "const uint8_t rdcd_injection_sizes[RDCD_INJECTION_COUNT] = {",
            *[f"    {program.fragment(n).size}," for n in program.injection], "};", ""]
    out += ["/* Role table: ids 1..14; 255 = any. */"]
    out += [f"#define RDCD_ROLE_{re.sub(r'[^A-Za-z0-9]', '_', r.name).upper()} {r.id}" for r in program.roles]
    out += ["", "int rdcd_instance_of(uint8_t role, uint8_t of) {",
            "    if (of == 255 || role == of) return 1;", "    switch (role) {"]
    for role in program.roles:
        others = [i for i in role.instance_of if i != role.id]
        test = " || ".join(f"of == {i}" for i in others) or "0"
        out.append(f"    case {role.id}: return {test};")
    out += ["    default: return 0;", "    }", "}", ""]
    return "\n".join(out)
