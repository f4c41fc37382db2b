"""The C form for the original firmware (docs/vm.md): it compiles with ``gcc -Wall -Werror``
against a header written from §10's interface, in the simulator build and the hardware build, and,
run with stand-ins for the firmware's functions, it sends exactly the compiled fragments in the
injection order on channels 0-7 with the program id counting up, and its role table is the
compiler's instance-of relation."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from rdcd_core.compiler import CompiledProgram
from rdcd_core.compiler.firmware_c import INJECTION_DELAY_MS
from rdcd_core.compiler.render import render_c
from tests.compiler.conftest import _compile, firmware_examples

GCC = shutil.which("gcc")
needs_gcc = pytest.mark.skipif(GCC is None, reason="gcc is not installed (CI has it)")

# The firmware's interface as docs/vm.md states it: the environment macros, the seven-byte
# context {x, y, z, rotation, incoming virtual channel, incoming physical channel, program_id},
# delay and sendProgramMaybe taking a uint8_t pointer, ARG_NORTH_SOUTH.
HEADER = """\
#include <stdint.h>
#ifdef USSR
typedef struct USSREnv USSREnv;
#define USSRONLY(x) x
#define USSRONLYC(x) x,
#else
#define USSRONLY(x)
#define USSRONLYC(x)
#endif
typedef struct {
    int8_t mod_x, mod_y, mod_z;
    uint8_t mod_rotation, incoming_virtual_channel, incoming_physical_channel, program_id;
} InterpreterContext;
#define ARG_EAST_WEST 1
#define ARG_NORTH_SOUTH 2
#define ARG_UP_DOWN 3
void delay(USSRONLYC(USSREnv *env) long ms);
void sendProgramMaybe(USSRONLYC(USSREnv *env) InterpreterContext *context, uint8_t channel,
                      uint8_t *program, uint8_t size);
"""

ACTIONS = """\
#include "firmware.h"
#include "program.c"
void actions_start(USSRONLY(USSREnv *env)) { dcd_action(USSRONLY(env)); }
"""

# A stand-in firmware that records what dcd_action does, and prints the role table.
RECORDER = """\
#include <stdio.h>
#include "firmware.h"
#include "program.c"
void delay(USSRONLYC(USSREnv *env) long ms) { printf("delay %ld\\n", ms); }
void sendProgramMaybe(USSRONLYC(USSREnv *env) InterpreterContext *context, uint8_t channel,
                      uint8_t *program, uint8_t size) {
    int i;
    printf("send %d %d %d %d %d %d", channel, context->program_id, context->mod_x, context->mod_y,
           context->mod_z, context->mod_rotation);
    printf(" %d", context->incoming_virtual_channel + context->incoming_physical_channel);
    for (i = 0; i < size; i++) printf(" %d", program[i]);
    printf("\\n");
}
int main(void) {
    int a, b;
    dcd_action(USSRONLY(0));
    for (a = 0; a < 256; a++)
        for (b = 0; b < 256; b++)
            if (check_role_instanceof((uint8_t)a, (uint8_t)b)) printf("role %d %d\\n", a, b);
    return 0;
}
"""


def _programs() -> list[tuple[str, CompiledProgram]]:
    return [(path.name, _compile(path.read_text(encoding="utf-8"), target="original"))
            for path in firmware_examples()]


def _gcc(directory: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([GCC, "-std=c99", "-Wall", "-Werror", *args], cwd=directory,
                          capture_output=True, text=True, timeout=120)


def _write(directory: Path, program: CompiledProgram, source: str) -> None:
    (directory / "firmware.h").write_text(HEADER)
    (directory / "program.c").write_text(render_c(program, source))
    (directory / "actions.c").write_text(ACTIONS)
    (directory / "recorder.c").write_text(RECORDER)


@needs_gcc
@pytest.mark.parametrize("build", [[], ["-DUSSR"]], ids=["hardware", "simulator"])
def test_every_example_compiles_without_warnings(tmp_path, build):
    for name, program in _programs():
        assert not program.has_errors, name
        _write(tmp_path, program, name)
        done = _gcc(tmp_path, *build, "-Wextra", "-fsyntax-only", "actions.c")
        assert done.returncode == 0, (name, done.stderr)


@needs_gcc
def test_dcd_action_sends_the_fragments_in_order_and_the_role_table_is_the_compilers(tmp_path):
    for name, program in _programs():
        _write(tmp_path, program, name)
        built = _gcc(tmp_path, "-DUSSR", "-o", "recorder", "recorder.c")
        assert built.returncode == 0, (name, built.stderr)
        lines = subprocess.run([str(tmp_path / "recorder")], capture_output=True, text=True,
                               timeout=60, check=True).stdout.splitlines()
        sends = [list(map(int, line.split()[1:])) for line in lines if line.startswith("send")]
        expected = [[channel, program_id, 0, 0, 0, 2, 0, *program.fragment(fragment).code]
                    for program_id, fragment in enumerate(program.injection) for channel in range(8)]
        assert sends == expected, name
        delays = [line for line in lines if line.startswith("delay")]
        assert delays == [f"delay {INJECTION_DELAY_MS}"] * len(program.injection)
        pairs = {tuple(map(int, line.split()[1:])) for line in lines if line.startswith("role")}
        expected_pairs = {(r.id, i) for r in program.roles for i in r.instance_of}
        expected_pairs |= {(a, a) for a in range(256)} | {(a, 255) for a in range(256)}
        assert pairs == expected_pairs, name


def test_the_file_has_the_firmware_interface(obstacle_text):
    program = _compile(obstacle_text, target="original")
    text = render_c(program, "obstacle_avoidance.rdcd")
    assert "static void dcd_action(USSRONLY(USSREnv *env)) {" in text
    assert "uint8_t check_role_instanceof(uint8_t self_role, uint8_t test_role) {" in text
    assert "InterpreterContext context = {0, 0, 0, ARG_NORTH_SOUTH, 0, 0, 0};" in text
    assert text.count("context.program_id++;") == len(program.injection)
    assert text.count(f"delay(USSRONLYC(env) {INJECTION_DELAY_MS});") == len(program.injection)
    for fragment in program.fragments:
        name = "rdcd_" + fragment.name
        assert f"#define SIZE_{name} {fragment.size}\n" in text
        assert f"unsigned char {name}[SIZE_{name} + 1] = {{" in text
        assert f"sendProgramMaybe(USSRONLYC(env) &context, channel, {name}, SIZE_{name});" in text
    array = re.search(r"rdcd_discover_\w+\[[^]]*\] = \{(.*?)\};", text, re.S).group(1)
    data = [int(n) for n in re.findall(r"(?<![\w@/])(\d+),", re.sub(r"/\*.*?\*/", "", array))]
    assert bytes(data) == program.fragments[0].code


@needs_gcc
@pytest.mark.parametrize("target", ["default", "original"])
def test_a_file_name_cannot_break_the_comments(tmp_path, obstacle_text, target):
    """issue 10: a path holding ``*/`` (or ``/*``, or a line break) ended the header comment."""
    program = _compile(obstacle_text, target=target)
    evil = "dir*/ int broken = ; /*x\n/*.rdcd"
    text = render_c(program, evil)
    assert "*/ int broken" not in text and "\n/*.rdcd" not in text
    (tmp_path / "firmware.h").write_text(HEADER)
    (tmp_path / "program.c").write_text(text)
    (tmp_path / "actions.c").write_text(ACTIONS if target == "original" else '#include "program.c"\n')
    done = _gcc(tmp_path, "-fsyntax-only", "actions.c")
    assert done.returncode == 0, done.stderr
