"""Shared helpers of the simulator tests: compile the example once, build small worlds."""

from __future__ import annotations

from functools import cache

from rdcd_core.compiler import compile_model
from rdcd_core.compiler.program import CompiledProgram
from rdcd_core.frontend import check_text
from sim.quiet import import_pybullet
from tests.conftest import EXAMPLES
from vm.isa.assembler import assemble

import_pybullet()

MIGRATE_CONTINUE = assemble("MIGRATE_CONTINUE")


@cache
def obstacle_program() -> CompiledProgram:
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    return compile_model(check_text(text).model, text=text)
