"""Reading and writing the user's files for the command line: one place for the rules.

Only regular files are read (a FIFO would wait for a writer forever, a device may never end);
text must be UTF-8; files are rewritten atomically (a full disk must not truncate a program).
Problems are ``InputError``: one line for the user, exit status 2.
"""

from __future__ import annotations

import errno
import os
import stat
import tempfile
from pathlib import Path


class InputError(Exception):
    """A usage or I/O problem: reported in one line, exit status 2."""


def collect_files(paths: list[str]) -> list[str]:
    """The ``*.rdcd`` files named by ``paths``: files as given, folders searched recursively."""
    files: list[str] = []
    for raw in paths:
        path = Path(raw)
        try:
            if not raw:  # Path("") is the current directory
                raise FileNotFoundError
            if path.is_dir():
                found = sorted(p for p in path.rglob("*.rdcd") if p.is_file())
                if not found:
                    raise InputError(f"no .rdcd files found in {raw}")
                files.extend(str(p) for p in found)
            elif path.exists():
                files.append(raw)
            else:
                raise FileNotFoundError
        except FileNotFoundError:
            raise InputError(f"no such file or directory: {raw!r}" if not raw else
                             f"no such file or directory: {raw}") from None
        except OSError as error:  # a name too long, a loop of links, a directory not listable
            raise InputError(f"cannot read {raw}: {error.strerror or error}") from None
    return files


def read_regular(path: str) -> bytes:
    """The bytes of a regular file. Opened without blocking and checked first: a FIFO would wait
    for a writer forever and a device may never end (OSError "not a regular file")."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    with os.fdopen(fd, "rb") as file:
        mode = os.fstat(fd).st_mode
        if stat.S_ISDIR(mode):
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), path)
        if not stat.S_ISREG(mode):
            raise OSError(errno.EINVAL, "not a regular file", path)
        return file.read()


def read_source(path: str) -> str:
    """The UTF-8 text of a program file, or an ``InputError`` saying why not."""
    name = path or "''"
    try:
        data = read_regular(path)
    except FileNotFoundError:
        raise InputError(f"no such file: {name}") from None
    except IsADirectoryError:
        raise InputError(f"{name} is a directory, not a file") from None
    except OSError as error:
        raise InputError(f"cannot read {name}: {error.strerror or error}") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise InputError(f"{name} is not UTF-8 text (byte {error.start})") from None


def write_atomically(path: str, text: str) -> None:
    """Replace a file's content all at once: written to a temporary file beside it, then renamed,
    so a failed write (a full disk) leaves the original untouched. Keeps the file's mode."""
    target = Path(path)
    try:
        mode = stat.S_IMODE(target.stat().st_mode)
    except OSError:
        mode = None
    fd, temporary = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as file:
            file.write(text)
            file.flush()
            os.fsync(file.fileno())
        if mode is not None:
            os.chmod(temporary, mode)
        os.replace(temporary, target)
    except BaseException:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        raise
