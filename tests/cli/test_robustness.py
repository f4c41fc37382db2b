"""Bad input to the command line: a clear one-line message, never a traceback, nothing lost.

Exit status 2 for usage and I/O problems, 1 for programs with errors. Every case runs the real
``rdcd`` as a child process (``python -m rdcd_core``), as a user or a CI script would.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli.helpers import assert_clean_failure, rdcd
from tests.conftest import EXAMPLES, ROOT

SNAKE = EXAMPLES / "snake_wave.rdcd"


def program_error_output(path: Path) -> list[str]:
    """What ``check`` (stdout) and ``compile`` (stderr) show for ``path``: both fail cleanly with 1."""
    shown = []
    for command in ("check", "compile"):
        done = rdcd(command, str(path))
        assert_clean_failure(done, 1)
        shown.append(done.stdout if command == "check" else done.stderr)
    return shown


def program(startup: str, extra: str = "") -> str:
    return f"role A {{\n  self.x() >= 0;\n{extra}  startup s() {{ {startup} }}\n}}\ndeployment {{ A }}\n"


# ---------------------------------------------------------------------------------- files

@pytest.fixture
def weird(tmp_path: Path) -> dict[str, Path]:
    """Files and non-files that are not RDCD programs."""
    paths = {
        "missing": tmp_path / "missing.rdcd",
        "empty_dir": tmp_path / "nothing",
        "dir_named_rdcd": tmp_path / "dir.rdcd",
        "fifo": tmp_path / "fifo.rdcd",
        "latin1": tmp_path / "latin1.rdcd",
        "garbage": tmp_path / "garbage.rdcd",
        "long_name": tmp_path / ("a" * 5000 + ".rdcd"),
    }
    paths["empty_dir"].mkdir()
    paths["dir_named_rdcd"].mkdir()
    os.mkfifo(paths["fifo"])
    paths["latin1"].write_bytes("role \xc4 { self.x() > 0; }\ndeployment { \xc4 }\n".encode("latin-1"))
    paths["garbage"].write_bytes(bytes(range(256)) * 8)
    return paths


CHECK_IO = [("missing", "no such file"), ("empty_dir", "no .rdcd files"),
            ("dir_named_rdcd", "no .rdcd files"), ("fifo", "not a regular file"),
            ("latin1", "not UTF-8"), ("garbage", "not UTF-8"), ("long_name", "too long")]


@pytest.mark.parametrize(("kind", "words"), CHECK_IO)
def test_check_io_errors(weird: dict[str, Path], kind: str, words: str) -> None:
    done = rdcd("check", str(weird[kind]))
    assert_clean_failure(done, 2, "rdcd check: ", words)
    assert done.stdout == ""


COMPILE_IO = [("missing", "no such file"), ("dir_named_rdcd", "is a directory"),
              ("fifo", "not a regular file"), ("latin1", "not UTF-8"), ("garbage", "not UTF-8"),
              ("long_name", "too long")]


@pytest.mark.parametrize(("kind", "words"), COMPILE_IO)
def test_compile_io_errors(weird: dict[str, Path], kind: str, words: str) -> None:
    done = rdcd("compile", str(weird[kind]))
    assert_clean_failure(done, 2, "rdcd compile: ", words)
    assert done.stdout == ""


def test_devices_are_not_read() -> None:
    """/dev/zero never ends: refused, not read until memory runs out."""
    if not Path("/dev/zero").exists():
        pytest.skip("no /dev/zero")
    assert_clean_failure(rdcd("check", "/dev/zero"), 2, "not a regular file")
    assert_clean_failure(rdcd("compile", "/dev/zero"), 2, "not a regular file")


def test_empty_path_is_not_the_current_directory() -> None:
    assert_clean_failure(rdcd("check", ""), 2, "no such file")
    assert_clean_failure(rdcd("compile", ""), 2, "no such file")


def test_a_good_file_and_a_missing_one_is_an_io_error(weird: dict[str, Path]) -> None:
    assert_clean_failure(rdcd("check", str(SNAKE), str(weird["missing"])), 2, "no such file")


# ---------------------------------------------------------------------------------- programs

@pytest.mark.parametrize("text", [
    "",
    "\n\n   \t\n",
    "\ufeff",
    "role",
    "}}}}{{{{",
    "role A { /* unterminated",
    "role A\x00 { self.x() > 0; }\ndeployment { A }\n",
    "".join(chr(c) for c in range(1, 0x250)),
    "x" * 2_000_000,  # one huge line
    "@ " * 50_000,  # 50,000 errors
], ids=["empty", "blank", "bom", "keyword", "braces", "comment", "nul", "unicode", "huge_line",
        "many_errors"])
def test_malformed_programs_are_program_errors(tmp_path: Path, text: str) -> None:
    path = tmp_path / "bad.rdcd"
    path.write_text(text, encoding="utf-8")
    for shown in program_error_output(path):
        assert "error[E" in shown and "E100" not in shown


@pytest.mark.parametrize("text", [
    program("self.setLed(" + "+".join(["1"] * 20_000) + ");"),  # a long flat expression
    program("self.setLed(" + "(" * 5000 + "1" + ")" * 5000 + ");"),
    program("self.setLed(" + "-" * 5000 + "1);"),
    program("if (self.x() > 0) " * 3000 + "self.setLed(1);"),
    program("self.setLed(" + "9" * 5000 + ");"),
], ids=["flat_sum", "parens", "negations", "ifs", "long_literal"])
def test_deep_and_long_programs_get_a_diagnostic(tmp_path: Path, text: str) -> None:
    path = tmp_path / "deep.rdcd"
    path.write_text(text, encoding="utf-8")
    for shown in program_error_output(path):
        assert "error[E" in shown and "E100" not in shown and "internal" not in shown
        assert max(len(line) for line in shown.splitlines() if "error[" in line) < 300


def _method_chain(n: int, inner: str = "") -> str:
    methods = "".join(f"  m{i}() {{ {inner} self.m{i + 1}(); }}\n" for i in range(n))
    return program("self.m0();", methods + f"  m{n}() {{ self.setLed(1); }}\n")


@pytest.mark.parametrize("n", [300, 3000])
def test_long_chains_of_inlined_methods(tmp_path: Path, n: int) -> None:
    """Plain methods calling one another thousands deep: E606, not a RecursionError (E100)."""
    path = tmp_path / "chain.rdcd"
    path.write_text(_method_chain(n), encoding="utf-8")
    for shown in program_error_output(path):
        assert "error[E606]" in shown and "nest too deeply" in shown and "E100" not in shown
        assert max(len(line) for line in shown.splitlines()) < 400


def test_a_short_chain_of_inlined_methods_compiles(tmp_path: Path) -> None:
    path = tmp_path / "chain.rdcd"
    path.write_text(_method_chain(10), encoding="utf-8")
    done = rdcd("compile", str(path))
    assert done.returncode == 0, done.stderr
    assert "SET_LED 1" in done.stdout


def test_code_past_255_bytes_is_too_large_not_an_internal_error(tmp_path: Path) -> None:
    """Jump targets beyond one byte used to crash the layout (ValueError, E100)."""
    path = tmp_path / "wide.rdcd"
    path.write_text(_method_chain(3, "if (self.x() > 0) " * 45 + "self.setLed(2);"), encoding="utf-8")
    done = rdcd("compile", str(path))
    assert_clean_failure(done, 1, "error[E601]")
    assert "E100" not in done.stderr


def test_recursive_cycle_message_stays_short(tmp_path: Path) -> None:
    methods = "".join(f"  m{i}() {{ self.m{(i + 1) % 2000}(); }}\n" for i in range(2000))
    path = tmp_path / "cycle.rdcd"
    path.write_text(program("self.m0();", methods), encoding="utf-8")
    done = rdcd("check", str(path))
    assert_clean_failure(done, 1, "")
    first = done.stdout.splitlines()[0]
    assert "error[E305]" in first and "more)" in first and len(first) < 300


# ---------------------------------------------------------------------------------- options

@pytest.mark.parametrize("args", [
    (),
    ("--bogus",),
    ("bogus",),
    ("check",),
    ("check", "--bogus", str(SNAKE)),
    ("check", "--format", "xml", str(SNAKE)),
    ("check", "--packet-budget", "abc", str(SNAKE)),
    ("check", "--packet-budget", "0", str(SNAKE)),
    ("check", "--packet-budget", "-5", str(SNAKE)),
    ("check", "--packet-budget", "100000000000000000000", str(SNAKE)),
    ("compile",),
    ("compile", str(SNAKE), str(SNAKE)),
    ("compile", "--format", "xml", str(SNAKE)),
    ("compile", "--max-packet", "0", str(SNAKE)),
    ("compile", "--max-packet", "abc", str(SNAKE)),
    ("compile", "--max-packet", "1e3", str(SNAKE)),
    ("compile", "--max-packet", "72", str(SNAKE)),
    ("compile", "-o", str(SNAKE)),
    ("fmt",),
    ("fmt", "--bogus", str(SNAKE)),
])
def test_usage_errors_exit_2(args: tuple[str, ...]) -> None:
    done = rdcd(*args)
    assert done.returncode == 2, (done.stdout, done.stderr)
    assert "Traceback" not in done.stderr
    assert done.stderr.strip(), "a usage error says what is wrong"
    assert done.stderr.strip().splitlines()[-1].startswith(("rdcd", "usage:", "  "))


def test_packet_budget_beyond_the_program_slot_is_refused_not_an_internal_error() -> None:
    """A 64-byte program slot takes at most 71-byte packets: more used to give E607 (internal)."""
    done = rdcd("check", "--packet-budget", "100", str(SNAKE))
    assert_clean_failure(done, 2, "--packet-budget must be 8..71")


# ---------------------------------------------------------------------------------- output

@pytest.mark.parametrize("target", ["/nonexistent/dir/x.txt", "directory"])
def test_compile_output_not_writable(tmp_path: Path, target: str) -> None:
    out = str(tmp_path) if target == "directory" else target
    assert_clean_failure(rdcd("compile", str(SNAKE), "-o", out), 2, "rdcd compile: ")


def test_compile_refuses_to_overwrite_its_program(tmp_path: Path) -> None:
    """`-o` naming the program itself (a slip of the finger) would replace it by the listing."""
    source = tmp_path / "p.rdcd"
    source.write_text(SNAKE.read_text(encoding="utf-8"), encoding="utf-8")
    done = rdcd("compile", str(source), "-o", str(tmp_path / "." / "p.rdcd"))
    assert_clean_failure(done, 2, "refusing to overwrite")
    assert source.read_text(encoding="utf-8") == SNAKE.read_text(encoding="utf-8")


@pytest.mark.parametrize("args", [("check", str(SNAKE)), ("compile", str(SNAKE)),
                                  ("compile", "--format", "json", str(SNAKE))])
def test_stdout_closed(args: tuple[str, ...]) -> None:
    """Started with stdout closed (`>&-`): the output cannot go anywhere; say so, status 2."""
    done = rdcd(*args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                preexec_fn=lambda: os.close(1), capture_output=False)
    assert_clean_failure(done, 2, "standard output is closed")


def test_stdout_closed_does_not_matter_with_output_file(tmp_path: Path) -> None:
    out = tmp_path / "out.txt"
    done = rdcd("compile", str(SNAKE), "-o", str(out), stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE, preexec_fn=lambda: os.close(1), capture_output=False)
    assert done.returncode == 0, done.stderr
    assert "discover_" in out.read_text(encoding="utf-8")


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
@pytest.mark.parametrize("args", [("check", str(SNAKE)), ("compile", str(SNAKE)),
                                  ("check", "--format", "json", str(EXAMPLES))])
def test_disk_full(args: tuple[str, ...]) -> None:
    """Output to a full disk is an I/O error: nothing is silently lost."""
    with open("/dev/full", "w") as full:
        done = rdcd(*args, stdout=full, stderr=subprocess.PIPE, capture_output=False)
    assert_clean_failure(done, 2, "No space left on device")


@pytest.mark.parametrize("args", [("check", "{many}"), ("check", "--format", "json", "{many}"),
                                  ("compile", str(EXAMPLES / "obstacle_avoidance.rdcd")),
                                  ("check", "--help")])
def test_reader_stops_early(tmp_path: Path, args: tuple[str, ...]) -> None:
    """`rdcd ... | head -1`: the reader goes away; no traceback, no warning at exit."""
    many = tmp_path / "many.rdcd"
    many.write_text("@ " * 20_000, encoding="utf-8")
    argv = [a.replace("{many}", str(many)) for a in args]
    child = subprocess.Popen([sys.executable, "-m", "rdcd_core", *argv], cwd=ROOT,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert child.stdout is not None and child.stderr is not None
    child.stdout.readline()
    child.stdout.close()
    stderr = child.stderr.read().decode("utf-8", "replace")
    child.wait(timeout=120)
    assert "Traceback" not in stderr and "Exception ignored" not in stderr, stderr
    assert child.returncode in (0, 1)


def test_output_encoding_without_the_characters(tmp_path: Path) -> None:
    """PYTHONIOENCODING=ascii and a program (or a path) with other characters: escaped, no crash."""
    path = tmp_path / "é.rdcd"
    path.write_text("role Ä { self.x() > 0; } // ü\ndeployment { Ä }\n", encoding="utf-8")
    done = rdcd("check", str(path), env={"PYTHONIOENCODING": "ascii"})
    assert "Traceback" not in done.stderr, done.stderr
    assert done.returncode in (0, 1)
    done = rdcd("check", str(tmp_path / "ü-missing.rdcd"), env={"PYTHONIOENCODING": "ascii"})
    assert_clean_failure(done, 2, "no such file")


# ------------------------------------------------------------------- rdcd fmt (read-only probes)

@pytest.mark.parametrize(("kind", "words"), [("missing", "no such file"), ("latin1", "not UTF-8"),
                                             ("garbage", "not UTF-8")])
def test_fmt_check_io_errors(weird: dict[str, Path], kind: str, words: str) -> None:
    done = rdcd("fmt", "--check", str(weird[kind]))
    assert_clean_failure(done, 2, "rdcd fmt: ", words)


def test_fmt_check_leaves_malformed_programs_alone(tmp_path: Path) -> None:
    path = tmp_path / "bad.rdcd"
    text = "role A { startup s() { self.setLed(" + "(" * 3000 + "1" + ")" * 3000 + "); } }\n"
    path.write_text(text, encoding="utf-8")
    done = rdcd("fmt", str(path))
    assert done.returncode == 1 and "Traceback" not in done.stderr, done.stderr
    assert path.read_text(encoding="utf-8") == text


def test_fmt_long_path(weird: dict[str, Path]) -> None:
    """cli_fmt lets the OSError of Path.is_dir (ENAMETOOLONG) out; the CLI root reports it."""
    assert_clean_failure(rdcd("fmt", "--check", str(weird["long_name"])), 2, "rdcd fmt: ",
                         "File name too long")


def test_fmt_empty_directory(weird: dict[str, Path]) -> None:
    assert_clean_failure(rdcd("fmt", "--check", str(weird["empty_dir"])), 2, "no .rdcd files")


def test_fmt_empty_path(tmp_path: Path) -> None:
    (tmp_path / "a.rdcd").write_text("role A{self.x()>0;}\ndeployment{A}\n", encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "fmt", "--check", ""], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert_clean_failure(done, 2, "no such file")


def test_fmt_fifo(weird: dict[str, Path]) -> None:
    try:
        done = subprocess.run([sys.executable, "-m", "rdcd_core", "fmt", "--check",
                               str(weird["fifo"])], cwd=ROOT, capture_output=True, text=True,
                              timeout=10)
    except subprocess.TimeoutExpired:
        pytest.fail("rdcd fmt blocked on a FIFO")
    assert_clean_failure(done, 2, "not a regular file")


def test_fmt_leaves_the_file_untouched_when_the_write_fails(tmp_path: Path) -> None:
    # A read-only folder: the temporary file cannot be created, the original must survive whole.
    import os

    if os.geteuid() == 0:
        pytest.skip("root writes into read-only folders")
    program = tmp_path / "ro" / "a.rdcd"
    program.parent.mkdir()
    original = "role A{self.x()>0;}\ndeployment{A}\n"
    program.write_text(original, encoding="utf-8")
    program.parent.chmod(0o500)
    try:
        result = rdcd("fmt", str(program))
    finally:
        program.parent.chmod(0o700)
    assert result.returncode == 2 and "unchanged" in result.stderr
    assert program.read_text(encoding="utf-8") == original


def test_fmt_write_is_atomic(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from rdcd_core import outputs

    program = tmp_path / "a.rdcd"
    program.write_text("old text\n", encoding="utf-8")

    def full_disk(*args: object, **kwargs: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(outputs.os, "fsync", full_disk)
    with pytest.raises(OSError):
        outputs.write_atomically(str(program), "new text that does not fit\n")
    assert program.read_text(encoding="utf-8") == "old text\n"
    assert [p.name for p in tmp_path.iterdir()] == ["a.rdcd"]


# ------------------------------------------------------------------- rdcd simulate (options)

@pytest.mark.parametrize("obstacle", ["wall:nan", "wall:inf", "box:nan,0,1,1", "wall:1e9", "wall:"])
def test_simulate_refuses_impossible_obstacles(obstacle: str) -> None:
    done = rdcd("simulate", "examples/obstacle_avoidance.rdcd", "--obstacle", obstacle, "--duration", "1")
    assert_clean_failure(done, 2, "--obstacle")


def test_simulate_refuses_a_folder_as_configuration(tmp_path: Path) -> None:
    done = rdcd("simulate", "examples/obstacle_avoidance.rdcd", "--config", str(tmp_path), "--duration", "1")
    assert_clean_failure(done, 2, "not a configuration file")


def test_simulate_does_not_wait_on_a_fifo(weird: dict[str, Path]) -> None:
    fifo = next((p for name, p in weird.items() if "fifo" in name), None)
    if fifo is None:
        pytest.skip("no FIFO here")
    done = rdcd("simulate", str(fifo), "--duration", "1", timeout=60)
    assert_clean_failure(done, 2, "not a regular file")
