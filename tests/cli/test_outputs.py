"""rdcd_core.outputs on its own: the paths a process cannot easily be driven into from outside
(an owner the rename cannot keep, a write failing after any number of bytes, a failed restore)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import BinaryIO

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rdcd_core import outputs
from rdcd_core.inputs import InputError
from rdcd_core.outputs import check_outputs, write_atomically, write_with


def _only(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_owner_not_keepable_means_rewriting_in_place(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """When the rename would hand the file to us (chown refused), fmt rewrites it in place."""
    path = tmp_path / "a.rdcd"
    path.write_text("old\n", encoding="utf-8")
    before = path.stat()
    monkeypatch.setattr(outputs, "_keep_owner", lambda temporary, info: False)
    write_atomically(str(path), "new text\n", keep_links=True)
    assert path.read_text(encoding="utf-8") == "new text\n" and path.stat().st_ino == before.st_ino
    assert _only(tmp_path) == ["a.rdcd"]


def test_outputs_are_renamed_even_when_the_owner_cannot_be_kept(tmp_path: Path,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "out.txt"
    path.write_text("old\n", encoding="utf-8")
    monkeypatch.setattr(outputs, "_keep_owner", lambda temporary, info: False)
    write_atomically(str(path), "new\n")
    assert path.read_text(encoding="utf-8") == "new\n" and _only(tmp_path) == ["out.txt"]


class _Fails(Exception):
    pass


@given(old=st.binary(max_size=300), new=st.binary(max_size=300), after=st.integers(0, 320),
       linked=st.booleans())
def test_a_write_failing_anywhere_leaves_old_or_new_and_nothing_else(tmp_path_factory: pytest.TempPathFactory,
                                                                     old: bytes, new: bytes, after: int,
                                                                     linked: bool) -> None:
    folder = tmp_path_factory.mktemp("w")
    path = folder / "f.rdcd"
    path.write_bytes(old)
    if linked:
        os.link(path, folder / "g.rdcd")

    def save(file: BinaryIO) -> None:
        file.write(new[:after])
        if after < len(new):
            raise _Fails
        file.write(new[after:])

    try:
        write_with(str(path), save, keep_links=True)
    except _Fails:
        assert path.read_bytes() == old
    else:
        assert path.read_bytes() == new
    assert _only(folder) == (["f.rdcd", "g.rdcd"] if linked else ["f.rdcd"])
    if linked:
        assert path.stat().st_ino == (folder / "g.rdcd").stat().st_ino


def test_a_failed_in_place_write_that_cannot_be_undone_keeps_the_backup(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "a.rdcd"
    path.write_text("the user's text\n", encoding="utf-8")
    os.link(path, tmp_path / "b.rdcd")

    def broken(real: str, data: bytes) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(outputs, "_overwrite", broken)
    with pytest.raises(OSError, match="old content is saved in") as info:
        write_atomically(str(path), "formatted\n", keep_links=True)
    backup = Path(info.value.strerror.split("saved in ")[1])
    assert backup.read_text(encoding="utf-8") == "the user's text\n"


def test_a_dangling_symlink_output_creates_its_target(tmp_path: Path) -> None:
    (tmp_path / "link.txt").symlink_to("target.txt")
    assert write_atomically(str(tmp_path / "link.txt"), "x") == str(tmp_path / "target.txt")
    assert (tmp_path / "link.txt").is_symlink() and (tmp_path / "target.txt").read_text() == "x"


@pytest.mark.parametrize(("outs", "words"), [
    ([("-o", "")], "empty path"),
    ([("-o", "a\0b")], "NUL"),
    ([("--a", "{d}/x"), ("--b", "{d}/sub/../x")], "name the same file"),
    ([("-o", "{d}/in.txt")], "is the program"),
    ([("-o", "{d}/in-link.txt")], "is the program"),
])
def test_check_outputs_refusals(tmp_path: Path, outs: list[tuple[str, str]], words: str) -> None:
    (tmp_path / "sub").mkdir()
    (tmp_path / "in.txt").write_text("input", encoding="utf-8")
    (tmp_path / "in-link.txt").symlink_to("in.txt")
    with pytest.raises(InputError, match=words):
        check_outputs([(o, p.format(d=tmp_path)) for o, p in outs],
                      [("the program", str(tmp_path / "in.txt"))])


def test_check_outputs_lets_devices_be_named_twice() -> None:
    check_outputs([("--report", "/dev/null"), ("--plot", "/dev/null")], [])
