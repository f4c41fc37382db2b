"""What the command line writes: never over an input, never two outputs on one file, always
atomically, through links as a user expects; and a reader that leaves early hides no error.

Every case runs the real ``rdcd`` as a child process, as a user or a CI script would.
"""

from __future__ import annotations

import json
import os
import resource
import signal
import stat
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.cli.helpers import assert_clean_failure, rdcd
from tests.conftest import EXAMPLES, ROOT

SOURCE = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
CONFIG = (ROOT / "sim" / "configs" / "car7.json").read_text(encoding="utf-8")
UNFORMATTED = "role A{self.x()>0;}\ndeployment{A}\n"
LATTICE = ("--world", "lattice", "--duration", "1")


@pytest.fixture
def files(tmp_path: Path) -> dict[str, Path]:
    """A program and a configuration, each with a symbolic link and a hard link to it."""
    program, config = tmp_path / "p.rdcd", tmp_path / "c.json"
    program.write_text(SOURCE, encoding="utf-8")
    config.write_text(CONFIG, encoding="utf-8")
    paths = {"program": program, "config": config}
    for name, path in list(paths.items()):
        (tmp_path / f"sym-{path.name}").symlink_to(path.name)
        os.link(path, tmp_path / f"hard-{path.name}")
        paths[f"{name}_symlink"] = tmp_path / f"sym-{path.name}"
        paths[f"{name}_hardlink"] = tmp_path / f"hard-{path.name}"
        paths[f"{name}_spelled"] = tmp_path / "." / path.name
    return paths


def _unchanged(files: dict[str, Path]) -> None:
    assert files["program"].read_text(encoding="utf-8") == SOURCE
    assert files["config"].read_text(encoding="utf-8") == CONFIG
    assert files["program_symlink"].is_symlink() and files["program_hardlink"].stat().st_nlink >= 2
    assert not [p for p in files["program"].parent.iterdir() if p.name.startswith(".")]


def _simulate(files: dict[str, Path], *extra: str) -> subprocess.CompletedProcess[str]:
    return rdcd("simulate", str(files["program"]), "--config", str(files["config"]), *LATTICE, *extra)


# ---------------------------------------------------------------- no output over an input

ALIASES = ["", "_symlink", "_hardlink", "_spelled"]


@pytest.mark.parametrize("option", ["--report", "--plot", "--record"])
@pytest.mark.parametrize("alias", ALIASES)
@pytest.mark.parametrize("victim", ["program", "config"])
def test_simulate_never_writes_over_an_input(files: dict[str, Path], option: str, alias: str,
                                             victim: str) -> None:
    target = files[victim + alias]
    extra = ("--world", "physics") if option == "--record" else ()
    if option != "--report":  # a picture needs a picture's extension: a link with one names the input
        picture = target.parent / f"pic-{victim}{alias}{'.gif' if option == '--record' else '.png'}"
        if alias == "_hardlink":
            os.link(files[victim], picture)
        else:
            picture.symlink_to(files[victim + alias])
        target = picture.parent / "." / picture.name if alias == "_spelled" else picture
    done = _simulate(files, option, str(target), *extra)
    assert_clean_failure(done, 2, "refusing to overwrite", option)
    assert done.stdout == "", "refused before the run"
    _unchanged(files)


@pytest.mark.parametrize("alias", ALIASES)
def test_compile_never_writes_over_its_program(files: dict[str, Path], alias: str) -> None:
    done = rdcd("compile", str(files["program"]), "-o", str(files["program" + alias]))
    assert_clean_failure(done, 2, "refusing to overwrite")
    _unchanged(files)


def test_compile_through_a_link_to_the_program_is_refused_too(files: dict[str, Path]) -> None:
    done = rdcd("compile", str(files["program_symlink"]), "-o", str(files["program_hardlink"]))
    assert_clean_failure(done, 2, "refusing to overwrite")
    _unchanged(files)


def test_shipped_configuration_is_an_input_too(tmp_path: Path, files: dict[str, Path]) -> None:
    shipped = ROOT / "sim" / "configs" / "car7.json"
    before = shipped.read_bytes()
    (tmp_path / "r.json").symlink_to(shipped)
    done = rdcd("simulate", str(files["program"]), "--config", "car7", *LATTICE,
                "--report", str(tmp_path / "r.json"))
    assert_clean_failure(done, 2, "refusing to overwrite", "configuration file")
    assert shipped.read_bytes() == before


@pytest.mark.parametrize(("first", "second"), [
    (("--report", "{d}/out.png"), ("--plot", "{d}/out.png")),
    (("--report", "{d}/out.png"), ("--plot", "{d}/./out.png")),
    (("--report", "{d}/old.png"), ("--plot", "{d}/link.png")),  # an existing file and a link to it
    (("--report", "{d}/new.png"), ("--plot", "{d}/dangling.png")),  # a new file and a link to it
])
def test_two_outputs_naming_one_file_are_refused(tmp_path: Path, files: dict[str, Path],
                                                  first: tuple[str, str], second: tuple[str, str]) -> None:
    (tmp_path / "old.png").write_bytes(b"old")
    (tmp_path / "link.png").symlink_to("old.png")
    (tmp_path / "dangling.png").symlink_to("new.png")
    args = [a.format(d=tmp_path) for a in (*first, *second)]
    done = _simulate(files, *args)
    assert_clean_failure(done, 2, "name the same file")
    assert done.stdout == ""
    assert (tmp_path / "old.png").read_bytes() == b"old" and not (tmp_path / "new.png").exists()


# ---------------------------------------------------------------- bad output paths, before any run

@pytest.mark.parametrize(("args", "words"), [
    (("--plot", "out.xyz"), ["unknown format '.xyz'", ".png", ".svg", ".pdf"]),
    (("--plot", "out.JSON"), ["unknown format '.JSON'"]),
    (("--plot", "out.pgf"), ["unknown format '.pgf'"]),  # LaTeX source, and needs TeX installed
    (("--record", "out.mp4", "--world", "physics"), ["unknown format '.mp4'", "accepted: .gif"]),
    (("--report", ""), ["--report ''", "empty path"]),
    (("--plot", ""), ["--plot ''", "empty path"]),
    (("--report", "{d}/missing/r.json"), ["missing does not exist"]),
    (("--report", "{d}"), ["is a folder"]),
    (("--report", "{d}/sub/"), ["names a folder"]),
    (("--report", "{d}/file.txt/r.json"), ["not a folder"]),
    (("--report", "{d}/loop.json"), ["a loop of symbolic links"]),
])
def test_simulate_checks_outputs_before_the_run(tmp_path: Path, files: dict[str, Path],
                                                args: tuple[str, ...], words: list[str]) -> None:
    (tmp_path / "file.txt").write_text("x", encoding="utf-8")
    (tmp_path / "loop.json").symlink_to("loop.json")
    done = _simulate(files, *(a.format(d=tmp_path) for a in args))
    assert_clean_failure(done, 2, "rdcd simulate: ", *words)
    assert "internal error" not in done.stderr and done.stdout == ""


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_simulate_refuses_an_unwritable_folder_before_the_run(tmp_path: Path, files: dict[str, Path]) -> None:
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    done = _simulate(files, "--report", str(locked / "r.json"))
    assert_clean_failure(done, 2, "permission denied")
    assert done.stdout == ""


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes read-only files")
@pytest.mark.parametrize("command", ["compile", "simulate"])
def test_read_only_outputs_are_not_replaced(tmp_path: Path, files: dict[str, Path], command: str) -> None:
    out = tmp_path / "out.json"
    out.write_text("keep\n", encoding="utf-8")
    out.chmod(0o444)
    args = ("-o", str(out)) if command == "compile" else (*LATTICE, "--report", str(out))
    assert_clean_failure(rdcd(command, str(files["program"]), *args), 2, "read-only")
    assert out.read_text(encoding="utf-8") == "keep\n"


def test_compile_empty_output_path_is_an_error(files: dict[str, Path]) -> None:
    done = rdcd("compile", str(files["program"]), "-o", "")
    assert_clean_failure(done, 2, "-o ''", "empty path")
    assert done.stdout == ""


def test_plot_without_extension_says_the_file_it_wrote(tmp_path: Path, files: dict[str, Path]) -> None:
    done = _simulate(files, "--plot", str(tmp_path / "noext"))
    assert done.returncode == 0, done.stderr
    written = tmp_path / "noext.png"
    assert f"plot: {written}" in done.stdout.splitlines()
    assert written.read_bytes()[:4] == b"\x89PNG" and not (tmp_path / "noext").exists()


@pytest.mark.parametrize(("name", "magic"), [("p.svg", b"<?xml"), ("p.PDF", b"%PDF"), ("p.jpg", b"\xff\xd8")])
def test_plot_format_follows_the_extension(tmp_path: Path, files: dict[str, Path], name: str,
                                           magic: bytes) -> None:
    done = _simulate(files, "--plot", str(tmp_path / name))
    assert done.returncode == 0, done.stderr
    assert (tmp_path / name).read_bytes().startswith(magic)


# ---------------------------------------------------------------- atomic writes

def _file_size_limit(limit: int) -> Callable[[], None]:
    """A child that can write no file beyond ``limit`` bytes: a full disk, for that child alone."""
    def limited() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # EFBIG instead of death
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return limited


OLD = b"the previous output, which must survive\n"


@pytest.mark.parametrize("case", ["compile", "report", "plot", "record"])
def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path: Path, files: dict[str, Path],
                                                             case: str) -> None:
    out = tmp_path / "out" / {"compile": "listing.txt", "report": "r.json", "plot": "p.png",
                              "record": "a.gif"}[case]
    out.parent.mkdir()
    out.write_bytes(OLD)
    args = {"compile": ("compile", str(files["program"]), "-o", str(out)),
            "report": ("simulate", str(files["program"]), *LATTICE, "--report", str(out)),
            "plot": ("simulate", str(files["program"]), *LATTICE, "--plot", str(out)),
            "record": ("simulate", str(files["program"]), "--duration", "0.5", "--record", str(out))}[case]
    done = rdcd(*args, preexec_fn=_file_size_limit(1000))
    assert_clean_failure(done, 2, "cannot write", "File too large")
    assert out.read_bytes() == OLD
    assert [p.name for p in out.parent.iterdir()] == [out.name]


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
def test_output_to_a_full_device_is_an_error() -> None:
    done = rdcd("compile", str(EXAMPLES / "obstacle_avoidance.rdcd"), "-o", "/dev/full")
    assert_clean_failure(done, 2, "No space left on device")


def test_output_to_a_device_is_written_directly() -> None:
    """/dev/null cannot be renamed over (and must never be): it is written as it is."""
    done = rdcd("compile", str(EXAMPLES / "obstacle_avoidance.rdcd"), "-o", "/dev/null")
    assert done.returncode == 0, done.stderr
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_a_new_output_gets_the_usual_mode(tmp_path: Path, files: dict[str, Path]) -> None:
    """The temporary file is private (0600); the output gets what the umask gives a new file."""
    out = tmp_path / "new.txt"
    done = rdcd("compile", str(files["program"]), "-o", str(out), preexec_fn=lambda: os.umask(0o027))
    assert done.returncode == 0, done.stderr
    assert stat.S_IMODE(out.stat().st_mode) == 0o640


def test_an_output_through_a_symlink_writes_the_file_and_keeps_the_link(tmp_path: Path,
                                                                       files: dict[str, Path]) -> None:
    real, link = tmp_path / "real.json", tmp_path / "link.json"
    real.write_text("old", encoding="utf-8")
    real.chmod(0o604)
    link.symlink_to(real.name)
    done = _simulate(files, "--report", str(link))
    assert done.returncode == 0, done.stderr
    assert link.is_symlink() and json.loads(real.read_text(encoding="utf-8"))["world"] == "lattice"
    assert stat.S_IMODE(real.stat().st_mode) == 0o604


# ---------------------------------------------------------------- rdcd fmt through links

def test_fmt_through_a_symlink_formats_the_file_and_keeps_the_link(tmp_path: Path) -> None:
    real = tmp_path / "real.rdcd"
    real.write_text(UNFORMATTED, encoding="utf-8")
    link = tmp_path / "sub" / "link.rdcd"
    link.parent.mkdir()
    link.symlink_to("../real.rdcd")
    done = rdcd("fmt", str(link))
    assert done.returncode == 0, done.stderr
    assert link.is_symlink() and os.readlink(link) == "../real.rdcd"
    assert real.read_text(encoding="utf-8") == "role A {\n  self.x() > 0;\n}\n\ndeployment { A }\n"
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["link.rdcd", "real.rdcd", "sub"]


def test_fmt_keeps_hard_links_mode_and_owner(tmp_path: Path) -> None:
    first, second = tmp_path / "a.rdcd", tmp_path / "b.rdcd"
    first.write_text(UNFORMATTED, encoding="utf-8")
    os.link(first, second)
    first.chmod(0o751)
    if os.geteuid() == 0:
        os.chown(first, 65534, 65534)
    before = first.stat()
    done = rdcd("fmt", str(first))
    assert done.returncode == 0, done.stderr
    after = first.stat()
    assert after.st_ino == before.st_ino == second.stat().st_ino and after.st_nlink == 2
    assert second.read_text(encoding="utf-8").startswith("role A {\n")
    assert (after.st_mode, after.st_uid, after.st_gid) == (before.st_mode, before.st_uid, before.st_gid)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.rdcd", "b.rdcd"], "no backup left"


@pytest.mark.skipif(os.geteuid() != 0, reason="only root can give a file to another owner")
def test_fmt_keeps_another_owner(tmp_path: Path) -> None:
    path = tmp_path / "a.rdcd"
    path.write_text(UNFORMATTED, encoding="utf-8")
    path.chmod(0o640)
    os.chown(path, 65534, 65534)
    assert rdcd("fmt", str(path)).returncode == 0
    info = path.stat()
    assert (info.st_uid, info.st_gid, stat.S_IMODE(info.st_mode)) == (65534, 65534, 0o640)
    assert path.read_text(encoding="utf-8").startswith("role A {\n")


@pytest.mark.parametrize("linked", [False, True])
def test_fmt_on_a_full_disk_keeps_the_text(tmp_path: Path, linked: bool) -> None:
    """The formatted text (45 bytes) does not fit, the original (33) does: a hard-linked file is
    rewritten in place and must get its old text back; no backup or temporary file is left."""
    path = tmp_path / "a.rdcd"
    path.write_text(UNFORMATTED, encoding="utf-8")
    if linked:
        os.link(path, tmp_path / "b.rdcd")
    done = rdcd("fmt", str(path), preexec_fn=_file_size_limit(40))
    assert_clean_failure(done, 2, "rdcd fmt: cannot write", "File too large", "unchanged")
    assert path.read_text(encoding="utf-8") == UNFORMATTED
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.rdcd", "b.rdcd"][:1 + linked]
    if linked:
        assert path.stat().st_ino == (tmp_path / "b.rdcd").stat().st_ino


# ---------------------------------------------------------------- links and folders: one wording

@pytest.mark.parametrize("command", [("check",), ("compile",), ("fmt",), ("fmt", "--check"),
                                     ("simulate", *LATTICE)])
def test_a_symlink_loop_is_reported_the_same_by_every_command(tmp_path: Path,
                                                              command: tuple[str, ...]) -> None:
    loop = tmp_path / "loop.rdcd"
    loop.symlink_to("loop.rdcd")
    done = rdcd(*command, str(loop))
    assert_clean_failure(done, 2, f"rdcd {command[0]}: cannot read {loop}: a loop of symbolic links")


@pytest.mark.parametrize("command", ["check", "fmt"])
def test_a_symlink_loop_inside_a_folder_is_not_skipped(tmp_path: Path, command: str) -> None:
    (tmp_path / "good.rdcd").write_text(UNFORMATTED, encoding="utf-8")
    (tmp_path / "loop.rdcd").symlink_to("loop.rdcd")
    done = rdcd(command, str(tmp_path))
    assert_clean_failure(done, 2, f"cannot read {tmp_path / 'loop.rdcd'}: a loop of symbolic links")
    assert (tmp_path / "good.rdcd").read_text(encoding="utf-8") == UNFORMATTED


def test_a_configuration_loop_is_reported_the_same_way(tmp_path: Path) -> None:
    loop = tmp_path / "loop.json"
    loop.symlink_to("loop.json")
    done = rdcd("simulate", str(EXAMPLES / "obstacle_avoidance.rdcd"), "--config", str(loop), *LATTICE)
    assert_clean_failure(done, 2, f"cannot read {loop}: a loop of symbolic links")


def test_a_broken_link_says_so(tmp_path: Path) -> None:
    link = tmp_path / "gone.rdcd"
    link.symlink_to("nowhere.rdcd")
    for command in ("check", "compile"):
        assert_clean_failure(rdcd(command, str(link)), 2, "no such file", "broken symbolic link")


def _too_deep(root: Path) -> Path:
    """A folder whose full path is longer than the system allows (PATH_MAX): even root cannot
    list it, so it stands for every folder that cannot be read."""
    fd = os.open(root, os.O_RDONLY)
    depth = 0
    try:
        while depth * 200 < 5000:
            name = "d" * 199
            os.mkdir(name, dir_fd=fd)
            inner = os.open(name, os.O_RDONLY, dir_fd=fd)
            os.close(fd)
            fd = inner
            depth += 1
        with open(os.open("hidden.rdcd", os.O_WRONLY | os.O_CREAT, 0o644, dir_fd=fd), "w") as file:
            file.write("@@@\n")
    finally:
        os.close(fd)
    return root


@pytest.mark.parametrize("command", [("check",), ("fmt", "--check")])
def test_check_dir_reports_a_folder_it_cannot_read(tmp_path: Path, command: tuple[str, ...]) -> None:
    (tmp_path / "good.rdcd").write_text(UNFORMATTED, encoding="utf-8")
    _too_deep(tmp_path)
    done = rdcd(*command, str(tmp_path))
    assert_clean_failure(done, 2, "cannot read the folder", "File name too long")
    assert done.stdout == ""


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads every folder")
def test_check_dir_reports_a_folder_without_permission(tmp_path: Path) -> None:
    (tmp_path / "good.rdcd").write_text(UNFORMATTED, encoding="utf-8")
    locked = tmp_path / "locked"
    locked.mkdir()
    (locked / "bad.rdcd").write_text("@@@\n", encoding="utf-8")
    locked.chmod(0)
    try:
        done = rdcd("check", str(tmp_path))
    finally:
        locked.chmod(0o700)
    assert_clean_failure(done, 2, f"cannot read the folder {locked}", "Permission denied")


# ---------------------------------------------------------------- the reader leaves early

def _reader_gone(*args: str, cwd: Path = ROOT) -> tuple[int, str]:
    """Runs rdcd with stdout and stderr on a pipe nobody reads any more (`| head -1` after the
    first line, at its most abrupt): (exit status, nothing on stderr is readable, so '')."""
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        child = subprocess.run([sys.executable, "-m", "rdcd_core", *args], cwd=cwd, stdout=write_end,
                               stderr=subprocess.PIPE, timeout=120)
    finally:
        os.close(write_end)
    return child.returncode, child.stderr.decode("utf-8", "replace")


@pytest.mark.parametrize("args", [("check", "{bad}"), ("check", "--format", "json", "{bad}"),
                                  ("check", "--format", "github", "{bad}"), ("fmt", "--check", "{dir}"),
                                  ("compile", "{bad}")])
def test_a_closed_pipe_does_not_hide_errors(tmp_path: Path, args: tuple[str, ...]) -> None:
    bad = tmp_path / "dir" / "bad.rdcd"
    bad.parent.mkdir()
    bad.write_text("@ " * 5000, encoding="utf-8")
    (tmp_path / "dir" / "ugly.rdcd").write_text(UNFORMATTED, encoding="utf-8")
    status, stderr = _reader_gone(*(a.format(bad=bad, dir=bad.parent) for a in args))
    assert status == 1, stderr
    assert "Traceback" not in stderr and "Exception ignored" not in stderr, stderr


def test_compile_errors_on_a_closed_stderr_pipe_still_fail(tmp_path: Path) -> None:
    bad = tmp_path / "bad.rdcd"
    bad.write_text("@ " * 5000, encoding="utf-8")
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        child = subprocess.run([sys.executable, "-m", "rdcd_core", "compile", str(bad)], cwd=ROOT,
                               stdout=subprocess.PIPE, stderr=write_end, timeout=120)
    finally:
        os.close(write_end)
    assert child.returncode == 1


def test_fmt_finishes_its_work_when_the_reader_leaves(tmp_path: Path) -> None:
    for i in range(3):
        (tmp_path / f"{i}.rdcd").write_text(UNFORMATTED, encoding="utf-8")
    status, stderr = _reader_gone("fmt", str(tmp_path))
    assert status == 0, stderr
    assert all(p.read_text(encoding="utf-8").startswith("role A {\n") for p in tmp_path.iterdir())


def test_simulate_writes_its_report_when_the_reader_leaves(tmp_path: Path) -> None:
    report = tmp_path / "r.json"
    status, stderr = _reader_gone("simulate", str(EXAMPLES / "obstacle_avoidance.rdcd"), *LATTICE,
                                  "--report", str(report))
    assert status == 0, stderr
    assert json.loads(report.read_text(encoding="utf-8"))["world"] == "lattice"


def test_a_good_program_with_the_reader_gone_is_still_0(tmp_path: Path) -> None:
    status, stderr = _reader_gone("check", str(EXAMPLES / "obstacle_avoidance.rdcd"))
    assert status == 0, stderr


def test_simulate_with_stdout_closed_still_writes_its_files(tmp_path: Path) -> None:
    """`>&-`: the summary cannot be shown (status 2, said in one line), the report is written."""
    report = tmp_path / "r.json"
    done = rdcd("simulate", str(EXAMPLES / "obstacle_avoidance.rdcd"), *LATTICE, "--report", str(report),
                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=lambda: os.close(1),
                capture_output=False)
    assert_clean_failure(done, 2, "standard output is closed")
    assert json.loads(report.read_text(encoding="utf-8"))["world"] == "lattice"


def test_pictures_to_a_device_keep_its_name() -> None:
    """`--plot /dev/null` has no extension, but is no file to add `.png` to (nor to replace)."""
    done = rdcd("simulate", str(EXAMPLES / "obstacle_avoidance.rdcd"), *LATTICE, "--plot", "/dev/null")
    assert done.returncode == 0, done.stderr
    assert "plot: /dev/null" in done.stdout.splitlines()
    assert not Path("/dev/null.png").exists() and stat.S_ISCHR(os.stat("/dev/null").st_mode)
