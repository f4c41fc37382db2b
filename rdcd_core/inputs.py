"""Reading the user's files for the command line: one place for the rules.

Only regular files are read (a FIFO would wait for a writer forever, a device may never end);
text must be UTF-8. Writing is in ``rdcd_core.outputs``.
Problems are ``InputError``: one line for the user, exit status 2.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path


class InputError(Exception):
    """A usage or I/O problem: reported in one line, exit status 2."""


def describe_os_error(error: OSError) -> str:
    """Why a path cannot be used, in the same words for every command (no file name)."""
    if error.errno == errno.ELOOP:
        return "a loop of symbolic links"
    if error.errno == errno.ENOENT:
        return "no such file or directory"
    if error.errno == errno.ENOTDIR:
        return "a part of the path is not a folder"
    return str(error.strerror or error)


def collect_files(paths: list[str]) -> list[str]:
    """The ``*.rdcd`` files named by ``paths``: files as given, folders searched recursively.

    Nothing is skipped silently: a sub-folder that cannot be listed is an error, and an entry named
    ``*.rdcd`` that is not a readable file (a broken link, a loop of links) is returned for
    ``read_source`` to report."""
    files: list[str] = []
    for raw in paths:
        if not raw:  # Path("") would be the current directory
            raise InputError("no such file or directory: ''")
        try:
            is_dir = stat.S_ISDIR(os.stat(raw).st_mode)
        except FileNotFoundError:
            raise InputError(f"no such file or directory: {raw}{_broken_link(raw)}") from None
        except OSError as error:  # a name too long, a loop of links, a folder not searchable
            raise InputError(f"cannot read {raw}: {describe_os_error(error)}") from None
        except ValueError:  # a NUL in the path
            raise InputError(f"cannot read {raw!r}: a path cannot contain a NUL character") from None
        if not is_dir:
            files.append(raw)
            continue
        found = _walk(raw)
        if not found:
            raise InputError(f"no .rdcd files found in {raw}")
        files.extend(found)
    return files


def _walk(folder: str) -> list[str]:
    def unreadable(error: OSError) -> None:
        raise InputError(f"cannot read the folder {error.filename}: {describe_os_error(error)}")

    found = []
    for parent, _, names in os.walk(folder, onerror=unreadable):  # links to folders not followed
        found += [os.path.join(parent, name) for name in names if name.endswith(".rdcd")]
    return sorted(found, key=lambda p: Path(p).parts)


def _broken_link(path: str) -> str:
    try:
        return f" (a broken symbolic link to {os.readlink(path)})" if os.path.islink(path) else ""
    except OSError:
        return ""


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
        raise InputError(f"no such file: {name}{_broken_link(path)}") from None
    except IsADirectoryError:
        raise InputError(f"{name} is a directory, not a file") from None
    except OSError as error:
        raise InputError(f"cannot read {name}: {describe_os_error(error)}") from None
    except ValueError:  # a NUL in the path
        raise InputError(f"cannot read {name!r}: a path cannot contain a NUL character") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise InputError(f"{name} is not UTF-8 text (byte {error.start})") from None
