"""Code for the connector and joint calls (opcodes 90..94, docs/vm.md): the argument, then the
instruction, which pushes its answer (an action's run waits for it). As a statement the answer
is dropped by a conditional jump to the next instruction (the VM has no POP)."""

from __future__ import annotations

from rdcd_core.compiler.context import Context
from rdcd_core.compiler.ir import Item, Label
from rdcd_core.syntax import ast

OPS = {"connect": "CONNECT", "disconnect": "DISCONNECT", "isConnected": "IS_CONNECTED",
       "isAligned": "IS_ALIGNED", "turnQuarters": "TURN_QUARTERS", "act": "ACT"}
# what the ATRON firmware's API calls them (native/include/atron.h); its DCD-VM has no opcode
FIRMWARE = {"connect": "_connect", "disconnect": "disconnect", "isConnected": "isConnected",
            "isAligned": "isOtherConnectorNearby", "turnQuarters": "rotate"}


def push(name: str, args: tuple, ctx: Context, out: list[Item], span: object) -> None:
    from rdcd_core.compiler.exprgen import emit, value

    op = OPS[name]
    if args and not isinstance(args[0], ast.Block):
        value(args[0], ctx, out)
    else:
        emit(out, "PUSH", 0, span=span)
    if not ctx.has(op):
        api = (f"the ATRON's C API has {FIRMWARE[name]}() in atron.h, but DCD-VM programs cannot call it"
               if name in FIRMWARE else "nor has the ATRON's C API one call for every action")
        ctx.cannot(span, f"self.{name}() needs {op}, which the {ctx.target.name} target does not run: the "  # type: ignore[arg-type]
                         f"firmware's DCD-VM has no instruction for it ({api})")
    emit(out, op, span=span)


def statement(name: str):  # type: ignore[no-untyped-def]
    def generate(args: tuple, ctx: Context, out: list[Item], span: object) -> None:
        from rdcd_core.compiler.exprgen import emit

        push(name, args, ctx, out, span)
        after = Label("dropped")
        emit(out, "IF_FALSE_GOTO", after, span=span)  # drops the answer
        out.append(after)
    return generate
