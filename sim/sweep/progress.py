"""The progress line of a sweep on stderr: done/total, failures and the time still to wait.

On a terminal the line is redrawn in place; elsewhere (a log file, CI) a line is printed every
tenth of the way or every 30 s, whichever comes first.
"""

from __future__ import annotations

import sys
import time
from typing import IO


def duration_text(seconds: float) -> str:
    seconds = int(round(seconds))
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"


class Progress:
    def __init__(self, total: int, already: int, stream: IO[str] | None = None) -> None:
        self.total, self.already, self.done, self.failed = total, already, already, 0
        self.stream = stream if stream is not None else sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.start = time.monotonic()
        self.last_print, self.last_tenth, self.printed = 0.0, -1, -1

    def line(self) -> str:
        ran = self.done - self.already
        left = self.total - self.done
        elapsed = time.monotonic() - self.start
        eta = duration_text(elapsed / ran * left) if ran and left else "-" if left else "0s"
        width = 30
        filled = int(width * self.done / self.total) if self.total else width
        return (f"[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} runs, "
                f"{self.failed} failed, ETA {eta}")

    def update(self, failed: bool) -> None:
        self.done += 1
        self.failed += failed
        self.show()

    def show(self, final: bool = False) -> None:
        try:
            if self.tty:
                self.stream.write("\r" + self.line() + ("\n" if final else ""))
                self.stream.flush()
                return
            now = time.monotonic()
            tenth = 10 * self.done // self.total if self.total else 10
            due = tenth != self.last_tenth or now - self.last_print >= 30
            if due or (final and self.done != self.printed):
                self.last_tenth, self.last_print, self.printed = tenth, now, self.done
                self.stream.write(self.line() + "\n")
                self.stream.flush()
        except (OSError, ValueError):  # a closed stderr must not stop the sweep
            pass
