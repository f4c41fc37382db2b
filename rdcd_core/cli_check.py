"""``rdcd check [--format text|json|github] [--warnings-as-errors] [--packet-budget N]
[--target default|original] [--config NAME|FILE] PATH...``

Exit status: 0 no errors, 1 errors (or warnings with --warnings-as-errors), 2 usage or I/O error.
"""

from __future__ import annotations

import argparse
import json
import sys

from rdcd_core.compiler.program import DEFAULT_PACKET_BUDGET, HEADER_BYTES, MAX_PROGRAM_BYTES
from rdcd_core.diagnostics import Diagnostic, Severity
from rdcd_core.frontend import CheckResult, check_text
from rdcd_core.inputs import InputError, collect_files, read_source
from rdcd_core.source import visible
from vm.isa.targets import TARGETS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("paths", nargs="+", metavar="PATH",
                        help="RDCD files, or directories searched recursively for *.rdcd")
    parser.add_argument("--format", choices=("text", "json", "github"), default="text",
                        help="output format (default: text)")
    parser.add_argument("--warnings-as-errors", action="store_true",
                        help="exit with status 1 on warnings too")
    parser.add_argument("--packet-budget", type=int, default=DEFAULT_PACKET_BUDGET, metavar="N",
                        help="packet size budget in bytes for the target checks "
                             f"(default: {DEFAULT_PACKET_BUDGET})")
    parser.add_argument("--config", default=None, metavar="NAME|FILE",
                        help="the starting configuration of the programs' sequences (shipped name, "
                             "snakeN, randomN-seedS or a file; default: the one each sequence names)")
    add_target_argument(parser)


def add_target_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--target", choices=tuple(TARGETS), default=None,
                        help="what the code must run on: 'default', this project's DCD-VM, or "
                             "'original', the ATRON firmware of 2007 (its instructions, stack 5, "
                             "100 instructions a run; default: default)")


def chosen_target(args: argparse.Namespace) -> str:
    """--target, or 'original' for --strict-isa (its old name), else 'default'."""
    if getattr(args, "target", None):
        return args.target
    return "original" if getattr(args, "strict_isa", False) else "default"


def check_packet_budget(flag: str, value: int) -> None:
    """A packet holds the header and at least one program byte, and at most a program slot."""
    low, high = HEADER_BYTES + 1, HEADER_BYTES + MAX_PROGRAM_BYTES
    if not low <= value <= high:
        raise InputError(f"{flag} must be {low}..{high} bytes, not {value}")


def run(args: argparse.Namespace) -> int:
    try:
        check_packet_budget("--packet-budget", args.packet_budget)
        sources = [(path, read_source(path)) for path in collect_files(args.paths)]
    except InputError as error:
        print(f"rdcd check: {error}", file=sys.stderr)
        return 2
    target = chosen_target(args)
    config = getattr(args, "config", None)
    if config is not None:
        from rdcd_core.sequences.check import load_structure

        try:
            load_structure(config)  # a bad --config is a usage error, not a diagnostic of each file
        except (ValueError, OSError) as error:
            print(f"rdcd check: --config: {error}", file=sys.stderr)
            return 2
    results = [(path, check_text(text, packet_budget=args.packet_budget, target=target, config=config))
               for path, text in sources]
    out = sys.stdout
    if args.format == "json":
        out.write(render_json(results) + "\n")
    elif args.format == "github":
        for path, result in results:
            for diagnostic in result.diagnostics:
                out.write(render_github(path, result, diagnostic) + "\n")
    else:
        for path, result in results:
            for diagnostic in result.diagnostics:
                out.write(render_text(path, result, diagnostic))
        out.write(summary(results) + "\n")
    return exit_status(results, args.warnings_as_errors)


def exit_status(results: list[tuple[str, CheckResult]], warnings_as_errors: bool) -> int:
    failing = {Severity.ERROR, Severity.WARNING} if warnings_as_errors else {Severity.ERROR}
    for _, result in results:
        if any(d.severity in failing for d in result.diagnostics):
            return 1
    return 0


def _positions(result: CheckResult, diagnostic: Diagnostic) -> tuple[int, int, int, int]:
    """1-based line, column, end line and end column (end exclusive)."""
    index = result.line_index
    start = index.line_col(diagnostic.span.start)
    end = index.line_col(diagnostic.span.end)
    return start.line + 1, start.column + 1, end.line + 1, end.column + 1


def render_text(path: str, result: CheckResult, diagnostic: Diagnostic) -> str:
    line, column, end_line, end_column = _positions(result, diagnostic)
    label = diagnostic.severity.label
    lines = [f"{path}:{line}:{column}: {label}[{diagnostic.code}]: {_clip(diagnostic.message)}"]
    index = result.line_index
    source = visible(index.line_text(line - 1))  # a form feed or U+2028 would move the caret
    if source.strip():
        width = (end_column - column) if end_line == line else len(source) - column + 1
        source, at, width = _excerpt(source, column - 1, width)
        gutter = " " * len(str(line))
        prefix = "".join(c if c == "\t" else " " for c in source[:at])
        lines += [f"{gutter} |", f"{line} | {source}", f"{gutter} | {prefix}{'^' * max(1, width)}"]
    for related in diagnostic.related:
        at = index.line_col(related.span.start)
        lines.append(f"  = note: {path}:{at.line + 1}:{at.column + 1}: {related.message}")
    for fix in diagnostic.fixes:
        lines.append(f"  = help: {fix.title}")
    return "\n".join(lines) + "\n\n"


def _clip(message: str, limit: int = 400) -> str:
    """A message of pathological length (it quotes a name of megabytes) cut in the middle."""
    if len(message) <= limit:
        return message
    return f"{message[:limit // 2]} ... {message[-limit // 2:]}"


def _excerpt(source: str, column: int, width: int, shown: int = 200) -> tuple[str, int, int]:
    """A long line cut to ``shown`` characters around the 0-based ``column`` (one diagnostic on a
    line of megabytes must not print megabytes): the text, the column and the width in it."""
    if len(source) <= shown:
        return source, column, width
    begin = max(0, min(column - shown // 4, len(source) - shown))
    end = begin + shown
    lead, tail = ("..." if begin > 0 else ""), ("..." if end < len(source) else "")
    return lead + source[begin:end] + tail, column - begin + len(lead), min(width, end - column)


def summary(results: list[tuple[str, CheckResult]]) -> str:
    errors = sum(d.severity is Severity.ERROR for _, r in results for d in r.diagnostics)
    warnings = sum(d.severity is Severity.WARNING for _, r in results for d in r.diagnostics)
    files = f"{len(results)} file{'s' if len(results) != 1 else ''} checked"
    if not errors and not warnings:
        return f"{files}: no problems"
    return (f"{files}: {errors} error{'s' if errors != 1 else ''}, "
            f"{warnings} warning{'s' if warnings != 1 else ''}")


def render_json(results: list[tuple[str, CheckResult]]) -> str:
    entries = []
    for path, result in results:
        for diagnostic in result.diagnostics:
            line, column, end_line, end_column = _positions(result, diagnostic)
            entries.append({"file": path, "line": line, "column": column, "end_line": end_line,
                            "end_column": end_column, "severity": diagnostic.severity.label,
                            "code": diagnostic.code, "message": diagnostic.message})
    return json.dumps({"files": len(results), "diagnostics": entries}, indent=2)


def _escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


def render_github(path: str, result: CheckResult, diagnostic: Diagnostic) -> str:
    line, column, end_line, end_column = _positions(result, diagnostic)
    kind = "error" if diagnostic.severity is Severity.ERROR else \
        "warning" if diagnostic.severity is Severity.WARNING else "notice"
    props = (f"file={_escape_property(path)},line={line},col={column},endLine={end_line},"
             f"endColumn={end_column},title={_escape_property(diagnostic.code)}")
    return f"::{kind} {props}::{_escape_data(diagnostic.message)}"
