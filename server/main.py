"""``rdcd-lsp``: the RDCD language server over stdio."""

from __future__ import annotations

import argparse
import gc
import logging
import sys

from server.config import Settings


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="rdcd-lsp", description="The RDCD language server (stdio).")
    parser.add_argument("--debounce-ms", type=float, default=None,
                        help="delay before re-checking a changed document (default 50)")
    parser.add_argument("--log-file", default=None, help="write the server log here")
    parser.add_argument("--log-level", default="WARNING", choices=["DEBUG", "INFO", "WARNING", "ERROR"])
    args = parser.parse_args(argv)
    target = {"filename": args.log_file} if args.log_file else {"stream": sys.stderr}
    logging.basicConfig(level=getattr(logging, args.log_level),
                        format="%(asctime)s %(name)s %(levelname)s %(message)s", **target)
    settings = Settings()
    if args.debounce_ms is not None:
        settings.debounce_ms = max(0.0, args.debounce_ms)
    from server.app import create_server

    server = create_server(settings)
    # the check allocates many short-lived objects; fewer full collections keep edits snappy
    gc.freeze()
    gc.set_threshold(50_000, 20, 50)
    server.start_io()
    return 0


if __name__ == "__main__":
    sys.exit(main())
