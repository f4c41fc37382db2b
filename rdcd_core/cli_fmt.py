"""``rdcd fmt [--check] PATH...``: format RDCD files in place, or list those that would change."""

from __future__ import annotations

import argparse
import sys

from rdcd_core.formatter import format_text
from rdcd_core.inputs import InputError, collect_files, read_source, write_atomically


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("paths", nargs="+", metavar="PATH", help=".rdcd files or folders holding them")
    parser.add_argument("--check", action="store_true",
                        help="do not write; list the files that would change and exit 1 if any")


def run(args: argparse.Namespace) -> int:
    # Every file is read before any is written: an unreadable one stops the run with nothing changed.
    try:
        sources = [(path, read_source(path)) for path in collect_files(args.paths)]
    except InputError as error:
        print(f"rdcd fmt: {error}", file=sys.stderr)
        return 2
    status = 0
    for path, text in sources:
        formatted = format_text(text)
        if formatted is None:
            print(f"{path}: has syntax errors, not formatted (run `rdcd check {path}`)", file=sys.stderr)
            status = max(status, 1)
            continue
        if formatted == text:
            continue
        if args.check:
            print(f"would reformat {path}")
            status = max(status, 1)
            continue
        try:
            write_atomically(path, formatted)
        except OSError as error:
            print(f"rdcd fmt: cannot write {path}: {error.strerror or error} (the file is unchanged)",
                  file=sys.stderr)
            return 2
        print(f"reformatted {path}")
    return status
