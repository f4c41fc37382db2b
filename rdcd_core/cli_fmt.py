"""``rdcd fmt [--check] PATH...``: format RDCD files in place, or list those that would change."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rdcd_core.formatter import format_text


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("paths", nargs="+", metavar="PATH", help=".rdcd files or folders holding them")
    parser.add_argument("--check", action="store_true",
                        help="do not write; list the files that would change and exit 1 if any")


def _files(paths: list[str]) -> list[Path]:
    files: list[Path] = []
    for name in paths:
        path = Path(name)
        if path.is_dir():
            files.extend(sorted(path.rglob("*.rdcd")))
        else:
            files.append(path)
    return files


def run(args: argparse.Namespace) -> int:
    status = 0
    for path in _files(args.paths):
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            print(f"rdcd fmt: cannot read {path}: {error}", file=sys.stderr)
            return 2
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
            path.write_text(formatted, encoding="utf-8")
        except OSError as error:
            print(f"rdcd fmt: cannot write {path}: {error}", file=sys.stderr)
            return 2
        print(f"reformatted {path}")
    return status
