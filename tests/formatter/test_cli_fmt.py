"""``rdcd fmt``: rewrite in place, --check, syntax errors (exit 1) and I/O errors (exit 2)."""

from __future__ import annotations

from pathlib import Path

from rdcd_core.cli import main

MESSY = "role A{constant c:=1;}\ndeployment{A}\n"
CLEAN = "role A {\n  constant c := 1;\n}\n\ndeployment { A }\n"


def test_rewrites_in_place(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "a.rdcd"
    path.write_text(MESSY)
    assert main(["fmt", str(path)]) == 0
    assert path.read_text() == CLEAN
    assert main(["fmt", "--check", str(path)]) == 0


def test_check_lists_and_fails(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    messy, clean = tmp_path / "messy.rdcd", tmp_path / "clean.rdcd"
    messy.write_text(MESSY)
    clean.write_text(CLEAN)
    assert main(["fmt", "--check", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "messy.rdcd" in out and "clean.rdcd" not in out
    assert messy.read_text() == MESSY


def test_syntax_error_and_missing_file(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    broken = tmp_path / "broken.rdcd"
    broken.write_text("role A { constant := ; }")
    assert main(["fmt", str(broken)]) == 1
    assert "syntax" in capsys.readouterr().err
    assert main(["fmt", str(tmp_path / "missing.rdcd")]) == 2
