"""``rdcd fmt [--check] PATH...``: format RDCD files in place, or list those that would change."""

from __future__ import annotations

import argparse
import sys

from rdcd_core.formatter import format_text
from rdcd_core.inputs import InputError, collect_files, describe_os_error, read_source
from rdcd_core.outputs import write_atomically


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
            # a link is followed (the real file formatted, the link kept); hard links, mode and
            # owner are kept
            write_atomically(path, formatted, keep_links=True)
        except OSError as error:
            kept = "" if "old content is saved" in str(error) else " (the file is unchanged)"
            print(f"rdcd fmt: cannot write {path}: {describe_os_error(error)}{kept}", file=sys.stderr)
            return 2
        print(f"reformatted {path}")
    return status
