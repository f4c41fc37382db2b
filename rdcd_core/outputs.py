"""Writing files for the command line: one place for the rules (reading is in ``rdcd_core.inputs``).

- No output overwrites an input, and no two outputs of one command name the same file. Checked
  before anything runs (``check_outputs``) by comparing the files themselves (device and inode), so
  a symbolic link, a hard link or another spelling of a path is caught as well as the path itself.
- Every write is atomic: the content goes to a temporary file beside the target, is flushed to the
  disk and renamed over the target. A failed write (a full disk) leaves the old file whole and no
  temporary file behind.
- A symbolic link is written through: the file it points to gets the content, the link stays.
- ``keep_links=True`` (``rdcd fmt``): a file with other hard links, or whose owner the rename could
  not keep, is rewritten in place instead, so every link sees the new text; its old content is kept
  in a backup beside it until the new content is on the disk, and put back if the write fails.
- A target that exists and is not a regular file (``/dev/null``, ``/dev/stdout``, a FIFO) is written
  directly: nothing can be renamed over it, and it holds nothing to lose.
"""

from __future__ import annotations

import errno
import io
import os
import stat
import tempfile
from collections.abc import Callable, Sequence
from typing import BinaryIO

from rdcd_core.inputs import InputError, describe_os_error

Save = Callable[[BinaryIO], object]


def check_outputs(outputs: Sequence[tuple[str, str]], inputs: Sequence[tuple[str, str]]) -> None:
    """Refuses (``InputError``, one line) outputs that cannot or must not be written.

    ``outputs`` are (option, path) pairs such as ``("-o", "out.txt")``; ``inputs`` are (what, path)
    pairs such as ``("the program", "car.rdcd")``. Refused: an empty path, a folder, a missing or
    unwritable folder, an input (through any link), and two outputs naming one file."""
    input_stats = []
    for what, path in inputs:
        try:
            input_stats.append((what, path, os.stat(path)))
        except (OSError, ValueError):  # not there (yet): it cannot be overwritten
            pass
    seen: list[tuple[object, str, str]] = []
    for option, path in outputs:
        info = _check_output(option, path)
        for what, input_path, input_stat in input_stats:
            if info is not None and os.path.samestat(info, input_stat):
                raise InputError(f"{option} {path} is {what} {input_path}; refusing to overwrite it")
        if info is not None and not stat.S_ISREG(info.st_mode):
            continue  # /dev/null twice is harmless
        key = (info.st_dev, info.st_ino) if info is not None else \
            os.path.normcase(os.path.realpath(path))
        for other_key, other_option, other_path in seen:
            if other_key == key:
                raise InputError(f"{other_option} {other_path} and {option} {path} name the same file; "
                                 "refusing to write one over the other")
        seen.append((key, option, path))


def _check_output(option: str, path: str) -> os.stat_result | None:
    """The output's ``stat`` (None when it does not exist yet), after the checks of one path."""
    where = f"{option} {path}"
    if not path:
        raise InputError(f"{option} '': an empty path names no file")
    if "\0" in path:
        raise InputError(f"{option} {path!r}: a path cannot contain a NUL character")
    if path.endswith(("/", os.sep)):
        raise InputError(f"{where}: names a folder, not a file")
    try:
        info: os.stat_result | None = os.stat(path)
    except FileNotFoundError:
        info = None
    except OSError as error:
        raise InputError(f"{where}: {describe_os_error(error)}") from None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise InputError(f"{where}: is a folder, not a file")
    if info is not None and not stat.S_ISREG(info.st_mode):  # a device or a FIFO: written directly
        if not os.access(path, os.W_OK):
            raise InputError(f"{where}: permission denied")
        return info
    real = os.path.realpath(path)  # a dangling link is written where it points
    folder = os.path.dirname(real)
    shown = os.path.dirname(path) or "."
    if not os.path.isdir(folder):
        raise InputError(f"{where}: the folder {shown} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{where}: cannot write in the folder {shown} (permission denied)")
    if info is not None and not os.access(path, os.W_OK):
        raise InputError(f"{where}: the file is read-only")
    return info


def write_atomically(path: str, content: str | bytes, *, keep_links: bool = False) -> str:
    """Writes ``content`` (text is UTF-8) to ``path`` atomically; the path of the file written."""
    data = content.encode("utf-8") if isinstance(content, str) else content
    return write_with(path, lambda file: file.write(data), keep_links=keep_links)


def write_with(path: str, save: Save, *, keep_links: bool = False) -> str:
    """Calls ``save(file)`` to write the new content of ``path`` into a binary file, then puts it in
    place atomically (see the module's rules); the path of the file written (links followed)."""
    try:
        os.stat(path)  # a loop of links raises ELOOP here; realpath would silently stop in it
    except FileNotFoundError:
        pass
    real = os.path.realpath(path)
    try:
        info: os.stat_result | None = os.stat(real)
    except FileNotFoundError:
        info = None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), path)
    if info is not None and not stat.S_ISREG(info.st_mode):
        with open(real, "wb") as file:
            save(file)
        return real
    if info is not None and not os.access(real, os.W_OK):  # read-only: the rename must not get round it
        raise PermissionError(errno.EACCES, "the file is read-only", path)
    if keep_links and info is not None and info.st_nlink > 1:
        _rewrite_in_place(real, save)
        return real
    fd, temporary = _temporary_beside(real, ".tmp")
    try:
        with os.fdopen(fd, "wb") as file:
            save(file)
            file.flush()
            os.fsync(file.fileno())
        if info is not None and not _keep_owner(temporary, info):
            if keep_links:  # the rename would give the file to us: rewrite it instead
                os.unlink(temporary)
                _rewrite_in_place(real, save)
                return real
        os.chmod(temporary, stat.S_IMODE(info.st_mode) if info is not None else 0o666 & ~_umask())
        os.replace(temporary, real)
    except BaseException:
        _remove(temporary)
        raise
    _sync_folder(os.path.dirname(real))
    return real


def _rewrite_in_place(real: str, save: Save) -> None:
    """The file's own inode gets the new content (hard links and owner stay), with its old content in
    a fsynced backup beside it until then; a failed write puts the old content back."""
    buffer = io.BytesIO()
    save(buffer)  # everything that can fail before the file is touched, first
    new = buffer.getvalue()
    with open(real, "rb") as file:
        old = file.read()
    fd, backup = _temporary_beside(real, ".backup")
    try:
        with os.fdopen(fd, "wb") as file:
            file.write(old)
            file.flush()
            os.fsync(file.fileno())
    except BaseException:
        _remove(backup)
        raise
    try:
        _overwrite(real, new)
    except BaseException as error:
        try:
            _overwrite(real, old)
        except OSError:
            code = error.errno if isinstance(error, OSError) else errno.EIO
            reason = error.strerror if isinstance(error, OSError) and error.strerror else str(error)
            raise OSError(code, f"{reason}; its old content is saved in {backup}", real) from None
        _remove(backup)
        raise
    _remove(backup)


def _overwrite(real: str, data: bytes) -> None:
    with open(real, "r+b") as file:
        file.write(data)
        file.truncate()
        file.flush()
        os.fsync(file.fileno())


def _keep_owner(temporary: str, info: os.stat_result) -> bool:
    """Gives the temporary file the target's owner and group; False if that is not allowed."""
    mine = os.stat(temporary)
    if (mine.st_uid, mine.st_gid) == (info.st_uid, info.st_gid):
        return True
    try:
        os.chown(temporary, info.st_uid, info.st_gid)
    except PermissionError:
        return False
    return True


def _temporary_beside(real: str, suffix: str) -> tuple[int, str]:
    folder, name = os.path.split(real)
    return tempfile.mkstemp(prefix=f".{name[:80]}.", suffix=suffix, dir=folder or ".")


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _remove(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def _sync_folder(folder: str) -> None:
    """The rename itself on the disk (best effort: not every system can open a folder)."""
    try:
        fd = os.open(folder or ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
