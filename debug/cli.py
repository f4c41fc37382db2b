"""``rdcd dap [--port N [--host H]]``: the Debug Adapter Protocol server, on standard input and
output (the default, what editors start) or on a TCP port, which listens on 127.0.0.1 unless
``--host`` names another address (anyone who reaches the port can run simulations and read the
program: a warning says so). On a port, clients are served one after another.
"""

from __future__ import annotations

import argparse
import os
import socket
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--port", type=int, default=None, metavar="N",
                        help="listen on this TCP port instead of standard input and output (0: any free "
                             "port, printed on standard error)")
    parser.add_argument("--host", default="127.0.0.1",
                        help="the address --port listens on (default: 127.0.0.1, this machine only)")


def run(args: argparse.Namespace) -> int:
    from sim.quiet import import_pybullet

    import_pybullet()  # its banner must not reach the protocol's stream
    if args.port is None:
        return _stdio()
    if not 0 <= args.port <= 65535:
        print(f"rdcd dap: --port must be 0..65535, not {args.port}", file=sys.stderr)
        return 2
    return _listen(args.host, args.port)


def _stdio() -> int:
    from debug.channel import Channel
    from debug.session import Session

    # the protocol gets its own copy of standard output; file descriptor 1 becomes standard error,
    # so that nothing else (a library's print, PyBullet's C output) can break a frame
    sys.stdout.flush()
    out = os.dup(1)
    os.dup2(2, 1)
    stdin = sys.stdin.buffer.raw if hasattr(sys.stdin.buffer, "raw") else sys.stdin.buffer

    def write(data: bytes) -> None:
        view = memoryview(data)
        while view:
            view = view[os.write(out, view):]

    Session(Channel(stdin.read, write)).serve()
    return 0


def _listen(host: str, port: int) -> int:
    from debug.channel import Channel
    from debug.session import Session

    if host not in ("127.0.0.1", "localhost", "::1"):
        print(f"rdcd dap: warning: --host {host} accepts other machines: anyone who can reach this "
              "port can run simulations and read the launched program", file=sys.stderr)
    try:
        server = socket.create_server((host, port), family=socket.AF_INET6 if ":" in host else socket.AF_INET)
    except OSError as e:
        print(f"rdcd dap: cannot listen on {host}:{port}: {e.strerror or e}", file=sys.stderr)
        return 2
    with server:
        print(f"rdcd dap: listening on {host}:{server.getsockname()[1]}", file=sys.stderr, flush=True)
        while True:
            try:
                connection, _ = server.accept()
            except KeyboardInterrupt:
                return 0
            with connection:
                Session(Channel(connection.recv, connection.sendall)).serve()
