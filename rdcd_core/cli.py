"""The ``rdcd`` command line: the composition root.

Each subcommand lives in its own module that exposes ``add_arguments(parser)`` and
``run(args) -> int``; exit status 0 = success, 1 = the input has errors, 2 = usage or I/O error.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import io
import os
import sys

from rdcd_core import __version__

SUBCOMMANDS: dict[str, tuple[str, str]] = {
    "check": ("rdcd_core.cli_check", "check RDCD programs and report diagnostics"),
    "compile": ("rdcd_core.cli_compile", "compile a program to DCD-VM bytecode fragments"),
    "fmt": ("rdcd_core.cli_fmt", "format RDCD programs"),
    "simulate": ("sim.cli_simulate", "run a program on a simulated ATRON robot"),
    "sweep": ("sim.sweep.cli", "run experiments: many simulations over a grid of options"),
    "dap": ("debug.cli", "debug a program in the simulator (Debug Adapter Protocol server)"),
}


def build_parser(selected: str | None = None) -> argparse.ArgumentParser:
    """The argument parser; only the ``selected`` subcommand's module is imported (the others
    would cost start-up time: ``simulate`` loads PyBullet)."""
    parser = argparse.ArgumentParser(prog="rdcd", description="The RDCD toolchain for ATRON modular robots.")
    parser.add_argument("--version", action="version", version=f"rdcd {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
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


class _ClosedOutput(io.TextIOBase):
    """Stands for a standard stream the process was started without (``>&-``): writing to it is
    an I/O error reported in one line, not an AttributeError on None."""

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        raise OSError(errno.EBADF, "standard output is closed")


class _ReaderMayLeave:
    """A standard stream whose reader may stop early (`rdcd check bad.rdcd | head -1`). The rest of
    the output is dropped, but the command runs to its end: its exit status (errors found, files
    written) must not turn into 0 because nobody read the last lines."""

    def __init__(self, stream: object) -> None:
        self._stream = stream
        self.reader_left = False

    def write(self, text: str) -> int:
        if not self.reader_left:
            try:
                return self._stream.write(text)  # type: ignore[attr-defined]
            except BrokenPipeError:
                self._reader_left()
        return len(text)

    def flush(self) -> None:
        if not self.reader_left:
            try:
                self._stream.flush()  # type: ignore[attr-defined]
            except BrokenPipeError:
                self._reader_left()

    def _reader_left(self) -> None:
        """The pipe goes to /dev/null: what is still buffered, and the interpreter's last flush,
        must not fail again (and print a warning at exit)."""
        self.reader_left = True
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self._stream.fileno())  # type: ignore[attr-defined]
            os.close(devnull)
        except (OSError, ValueError, AttributeError, io.UnsupportedOperation):
            pass

    def __getattr__(self, name: str) -> object:
        return getattr(self._stream, name)


def _prepare_streams() -> None:
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115 (lives as long as we do)
    if sys.stdout is None:
        sys.stdout = _ClosedOutput()
    for stream in (sys.stdout, sys.stderr):
        # paths and programs may hold characters the output encoding lacks (PYTHONIOENCODING=ascii)
        if getattr(stream, "errors", None) == "strict" and hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    _prepare_streams()
    streams = sys.stdout, sys.stderr
    if not isinstance(sys.stdout, _ClosedOutput):
        sys.stdout = _ReaderMayLeave(sys.stdout)  # type: ignore[assignment]
    sys.stderr = _ReaderMayLeave(sys.stderr)  # type: ignore[assignment]
    try:
        return _run(argv)
    finally:
        sys.stdout, sys.stderr = streams


def _run(argv: list[str]) -> int:
    selected = _selected_command(argv)
    name = f"rdcd {selected}" if selected else "rdcd"  # known before the slow imports a Ctrl-C may cut
    try:
        parser = build_parser(selected)
        args = parser.parse_args(argv)  # --help and --version write to stdout too
        if args.command is None:
            parser.print_help(sys.stderr)
            return 2
        name = f"rdcd {args.command}"
        if getattr(args, "unavailable", None):
            print(f"rdcd: '{args.unavailable}' is not available in this build", file=sys.stderr)
            return 2
        status = int(args.handler(args))
        sys.stdout.flush()  # a full disk must show here, not after main has returned
        return status
    except KeyboardInterrupt:  # Ctrl-C: one line, no traceback; outputs are written atomically, so
        # nothing half-written is left (rdcd sweep says itself what it kept)
        _report(f"{name}: interrupted")
        return 130
    except OSError as error:  # an I/O error no subcommand caught: writing the output, mostly
        where = f"{error.filename}: " if error.filename else "cannot write the output: "
        _report(f"{name}: {where}{error.strerror or error}")
        return 2
    except Exception as error:  # a bug: one clear line, not a traceback (status 1, as E100)
        _report(f"{name}: internal error: {type(error).__name__}: {error}; please report this bug")
        return 1


def _report(message: str) -> None:
    try:
        print(message, file=sys.stderr)
    except (OSError, ValueError):
        pass


if __name__ == "__main__":
    sys.exit(main())
