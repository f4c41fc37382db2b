"""`rdcd check` and `rdcd fmt` as real processes on files with every kind of line break: a
diagnostic names the line an editor shows, its snippet is that line with the caret under the
fault, and formatting keeps the file's own line break."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ROOT


def rdcd(*args: str) -> subprocess.CompletedProcess[str]:
    done = subprocess.run([sys.executable, "-m", "rdcd_core", *args], cwd=ROOT, capture_output=True,
                          timeout=60)
    # decoded by hand: text=True would turn every \r into \n and hide what the command printed
    return subprocess.CompletedProcess(done.args, done.returncode, done.stdout.decode("utf-8"),
                                       done.stderr.decode("utf-8"))


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "prog.rdcd"
    path.write_bytes(text.encode("utf-8"))
    return path


def snippet(out: str) -> tuple[str, str]:
    """The quoted source line and the caret line of the first diagnostic."""
    lines = out.split("\n")
    source = next(line for line in lines if line[:1].isdigit() and " | " in line)
    caret = lines[lines.index(source) + 1]
    return source, caret


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_a_diagnostic_after_lone_cr_lines_is_on_its_line(tmp_path: Path, newline: str) -> None:
    text = newline.join(["role A {", "  // one", "  self.y() > EAST_WST;", "}", "deployment { A }", ""])
    path = write(tmp_path, text)
    done = rdcd("check", str(path))
    assert done.returncode == 1
    assert f"{path}:3:14: error[E" in done.stdout, done.stdout
    source, caret = snippet(done.stdout)
    assert source == "3 |   self.y() > EAST_WST;"
    assert caret.index("^") == source.index("EAST_WST")
    report = json.loads(rdcd("check", "--format", "json", str(path)).stdout)
    assert [(d["line"], d["column"]) for d in report["diagnostics"]] == [(3, 14)]


@pytest.mark.parametrize("char", ["\f", "\v", "\x1c", "\x85", "\u2028", "\u2029"])
def test_characters_that_are_no_line_break_keep_the_line_and_the_caret(tmp_path: Path, char: str) -> None:
    text = f"role A {{ // a{char}b\r  self.y() > 0;{char} self.y() > EAST_WST;\r}}\rdeployment {{ A }}\r"
    path = write(tmp_path, text)
    done = rdcd("check", str(path))
    assert done.returncode == 1
    first = done.stdout.split("\n")[0]
    column = 16 if char != "\f" else 0  # a form feed is white space; the others are bad characters
    if column:
        assert first.startswith(f"{path}:2:{column}: error[E001]"), done.stdout
    source, caret = snippet(done.stdout)
    assert source.startswith("2 |   self.y() > 0;")
    assert len(source.splitlines()) == 1 and "\f" not in source and "\v" not in source
    assert "EAST_WST" in source and "\r" not in source
    if column:
        assert caret.index("^") == source.index("0;") + 2


@pytest.mark.parametrize("newline", ["\r\n", "\r"])
def test_fmt_keeps_the_files_line_break_inside_block_comments_too(tmp_path: Path, newline: str) -> None:
    text = newline.join(["role A{", "  /* a", "     b\nc */", "  self.y()>- -1;", "}", "deployment{A}", ""])
    path = write(tmp_path, text)
    done = rdcd("fmt", str(path))
    assert done.returncode == 0, done.stderr
    expected = newline.join(["role A {", "  /* a", "     b", "c */", "  self.y() > - -1;", "}", "",
                             "deployment { A }", ""])
    assert path.read_bytes().decode("utf-8") == expected
    assert rdcd("fmt", "--check", str(path)).returncode == 0
