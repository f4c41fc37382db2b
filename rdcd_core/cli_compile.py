"""``rdcd compile FILE [--format listing|json|c] [--max-packet 50] [--target default|original] [-o OUT]``

``--strict-isa`` is kept as an alias of ``--target original``: it promised code for the original
DCD-VM, which is what that target delivers (only the instructions the firmware runs, its limits).

Exit status: 0 compiled, 1 the program has errors, 2 usage or I/O error.
"""

from __future__ import annotations

import argparse
import sys

from rdcd_core.cli_check import add_target_argument, check_packet_budget, chosen_target, render_text
from rdcd_core.compiler import CompiledProgram, add_source_lines, compile_model
from rdcd_core.compiler.program import DEFAULT_PACKET_BUDGET, HEADER_BYTES
from rdcd_core.compiler.render import render_c, render_json, render_listing
from rdcd_core.diagnostics import Diagnostic, Severity
from rdcd_core.frontend import CheckResult, check_text
from rdcd_core.inputs import InputError, describe_os_error, read_source
from rdcd_core.outputs import check_outputs, write_atomically


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE", help="the RDCD program")
    parser.add_argument("--format", choices=("listing", "json", "c"), default="listing",
                        help="output format (default: listing)")
    parser.add_argument("--max-packet", type=int, default=DEFAULT_PACKET_BUDGET, metavar="N",
                        help=f"packet budget in bytes, {HEADER_BYTES} header bytes included "
                             f"(default: {DEFAULT_PACKET_BUDGET})")
    add_target_argument(parser)
    parser.add_argument("--strict-isa", action="store_true",
                        help="alias of --target original (kept for compatibility)")
    parser.add_argument("-o", "--output", metavar="OUT",
                        help="write the output to this file (atomically; never over the program), "
                             "not to stdout")


def compile_text(text: str, *, packet_budget: int = DEFAULT_PACKET_BUDGET, strict_isa: bool = False,
                 target: str | None = None, reverse: str | None = None
                 ) -> tuple[CheckResult, CompiledProgram | None, list[Diagnostic]]:
    """Checks ``text`` and, if it has no errors, compiles it for ``target`` (``strict_isa``: the
    original target): the check result, the program (None after errors) and every diagnostic, the
    compiler's own ones that the check had not found added. ``reverse``: a sequence compiled to
    run backwards."""
    name = target or ("original" if strict_isa else "default")
    result = check_text(text, packet_budget=packet_budget, target=name)
    diagnostics = list(result.diagnostics)
    if result.has_errors:
        return result, None, diagnostics
    if result.compiled is not None and reverse is None:  # the check compiled it: add the lines
        program = result.compiled
        add_source_lines(program.fragments, result.line_index)
        return result, program, diagnostics
    program = compile_model(result.model, packet_budget=packet_budget, target=name, text=text,
                            reverse=reverse)
    known = {(d.code, d.span) for d in diagnostics}
    diagnostics += [d for d in program.diagnostics if (d.code, d.span) not in known]
    return result, program, diagnostics


def run(args: argparse.Namespace) -> int:
    try:
        check_packet_budget("--max-packet", args.max_packet)
        text = read_source(args.file)
        if args.output is not None:  # before compiling: `-o ''` or `-o PROGRAM` is a slip, said at once
            check_outputs([("-o", args.output)], [("the program", args.file)])
    except InputError as error:
        print(f"rdcd compile: {error}", file=sys.stderr)
        return 2
    try:
        result, program, diagnostics = compile_text(text, packet_budget=args.max_packet,
                                                    target=chosen_target(args))
    except Exception as error:  # a compiler bug: one clear line, not a traceback
        print(f"rdcd compile: internal compiler error: {type(error).__name__}: {error}; "
              "please report this bug", file=sys.stderr)
        return 1
    for diagnostic in diagnostics:
        sys.stderr.write(render_text(args.file, result, diagnostic))
    if program is None or any(d.severity is Severity.ERROR for d in diagnostics):
        return 1
    output = {"json": lambda: render_json(program) + "\n", "c": lambda: render_c(program, args.file),
              "listing": lambda: render_listing(program)}[args.format]()
    if args.output is not None:
        try:
            write_atomically(args.output, output)
        except OSError as error:
            print(f"rdcd compile: cannot write {args.output}: {describe_os_error(error)}", file=sys.stderr)
            return 2
    else:
        sys.stdout.write(output)
    return 0
