"""The ``rdcd`` command line: the composition root (DESIGN.md).

Each subcommand lives in its own module that exposes ``add_arguments(parser)`` and
``run(args) -> int``; exit status 0 = success, 1 = the input has errors, 2 = usage or I/O error.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from rdcd_core import __version__

SUBCOMMANDS: dict[str, tuple[str, str]] = {
    "check": ("rdcd_core.cli_check", "check RDCD programs and report diagnostics"),
    "compile": ("rdcd_core.cli_compile", "compile a program to DCD-VM bytecode fragments"),
    "fmt": ("rdcd_core.cli_fmt", "format RDCD programs"),
    "simulate": ("sim.cli_simulate", "run a program on a simulated ATRON robot"),
}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser(selected: str | None = None) -> argparse.ArgumentParser:
    """The argument parser; only the ``selected`` subcommand's module is imported (the others
    would cost start-up time: ``simulate`` loads PyBullet)."""
    parser = _Parser(prog="rdcd", description="The RDCD toolchain for ATRON modular robots.")
    parser.add_argument("--version", action="version", version=f"rdcd {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (module_name, help_text) in SUBCOMMANDS.items():
        sub = commands.add_parser(name, help=help_text, description=help_text)
        if name != selected:
            continue
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as error:
            if error.name is None or not module_name.startswith(error.name):
                raise
            sub.set_defaults(unavailable=name)
            continue
        module.add_arguments(sub)
        sub.set_defaults(handler=module.run)
    return parser


def _selected_command(argv: list[str]) -> str | None:
    for word in argv:
        if not word.startswith("-"):
            return word if word in SUBCOMMANDS else None
    return None


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parser = build_parser(_selected_command(argv))
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    if getattr(args, "unavailable", None):
        print(f"rdcd: '{args.unavailable}' is not available in this build", file=sys.stderr)
        return 2
    try:
        return int(args.handler(args))
    except KeyboardInterrupt:
        print("rdcd: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
