"""``rdcd-lsp``: the RDCD language server over stdio.

Exit status: 0 after ``shutdown`` and ``exit``, 1 on ``exit`` without ``shutdown`` or when the client
went away, 2 for unusable options (one line on stderr), 128+N on signal N.
"""

from __future__ import annotations

import argparse
import gc
import logging
import os
import sys
from typing import NoReturn

from server.config import SettingError, Settings, parse_debounce

LOG_FORMAT = "%(asctime)s %(name)s %(levelname)s %(message)s"


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        """One line, as for every other unusable option (argparse adds the usage)."""
        self.exit(2, f"{self.prog}: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="rdcd-lsp", description="The RDCD language server (stdio).")
    parser.add_argument("--debounce-ms", default=None, metavar="MS",
                        help="delay before re-checking a changed document, 0..10000 (default 50; "
                             "also RDCD_LSP_DEBOUNCE_MS)")
    parser.add_argument("--log-file", default=None,
                        help="append the server log to this file (default: stderr)")
    parser.add_argument("--log-level", default="WARNING", choices=["DEBUG", "INFO", "WARNING", "ERROR"])
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    debounce = None
    if args.debounce_ms is not None:
        try:
            debounce = parse_debounce(args.debounce_ms, "--debounce-ms")
        except SettingError as error:
            parser.error(str(error))
    try:
        handler = _log_handler(args.log_file)
    except (OSError, ValueError) as error:
        reason = getattr(error, "strerror", None) or str(error)
        print(f"rdcd-lsp: cannot write the log file {args.log_file}: {reason}", file=sys.stderr)
        return 2
    handler.setFormatter(logging.Formatter(LOG_FORMAT))
    logging.basicConfig(level=getattr(logging, args.log_level), handlers=[handler])
    logging.raiseExceptions = False  # a log that cannot be written (full disk) must not print tracebacks
    settings, problems = Settings.from_environment(os.environ)
    for problem in problems:
        print(f"rdcd-lsp: {problem}", file=sys.stderr)
        if args.log_file:
            logging.getLogger("rdcd.server").warning("%s", problem)
    if debounce is not None:
        settings.debounce_ms = debounce
    return _serve(settings)


def _log_handler(path: str | None) -> logging.Handler:
    if not path:
        return logging.StreamHandler(sys.stderr)
    if os.path.isdir(path):
        raise IsADirectoryError(21, "it is a folder")
    return logging.FileHandler(path, encoding="utf-8")


def _serve(settings: Settings) -> int:
    from server import scratch
    from server.app import create_server
    from server.stdio import serve_stdio

    server = create_server(settings)
    # the check allocates many short-lived objects; fewer full collections keep edits snappy
    gc.freeze()
    gc.set_threshold(50_000, 20, 50)
    try:
        return serve_stdio(server)
    finally:
        scratch.remove()


if __name__ == "__main__":
    sys.exit(main())
