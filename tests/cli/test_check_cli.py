"""`rdcd check`: every output format and every exit status, in-process and as a real process."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from rdcd_core.cli import main
from tests.conftest import EXAMPLES, ROOT

BAD = "role A {\n  self.center_position == EAST_WST;\n}\ndeployment { A }\n"
WARN = "role A { self.x() == 0; }\nrole Unused { self.x() == 2; }\ndeployment { A }\n"


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)
    # pybullet prints a banner when `rdcd` imports the simulate subcommand: not ours to judge here
    done.stderr = "".join(line for line in done.stderr.splitlines(keepends=True)
                          if not line.startswith("pybullet build time"))
    return done


@pytest.fixture
def files(tmp_path: Path) -> dict[str, Path]:
    paths = {"bad": tmp_path / "bad.rdcd", "warn": tmp_path / "warn.rdcd"}
    paths["bad"].write_text(BAD, encoding="utf-8")
    paths["warn"].write_text(WARN, encoding="utf-8")
    return paths


def test_clean_examples_exit_0_subprocess() -> None:
    done = _run(str(EXAMPLES / "obstacle_avoidance.rdcd"), str(EXAMPLES / "snake_wave.rdcd"))
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip() == "2 files checked: no problems"


def test_text_format_with_caret_subprocess(files: dict[str, Path]) -> None:
    done = _run(str(files["bad"]))
    assert done.returncode == 1
    lines = done.stdout.splitlines()
    assert lines[0] == (f"{files['bad']}:2:27: error[E201]: unknown name 'EAST_WST'; "
                        "did you mean 'EAST_WEST'?")
    assert lines[2] == "2 |   self.center_position == EAST_WST;"
    assert lines[3] == "  |                           ^^^^^^^^"
    assert lines[-1] == "1 file checked: 1 error, 0 warnings"
    assert done.stderr == ""


def test_json_format_in_process(files: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "--format", "json", str(files["bad"]), str(files["warn"])]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["files"] == 2
    first = data["diagnostics"][0]
    assert first == {"file": str(files["bad"]), "line": 2, "column": 27, "end_line": 2,
                     "end_column": 35, "severity": "error", "code": "E201",
                     "message": "unknown name 'EAST_WST'; did you mean 'EAST_WEST'?"}
    assert [d["code"] for d in data["diagnostics"]] == ["E201", "W504"]


def test_github_format_subprocess(files: dict[str, Path]) -> None:
    done = _run("--format", "github", str(files["bad"]), str(files["warn"]))
    assert done.returncode == 1
    lines = done.stdout.splitlines()
    assert lines[0] == (f"::error file={files['bad']},line=2,col=27,endLine=2,endColumn=35,"
                        "title=E201::unknown name 'EAST_WST'; did you mean 'EAST_WEST'?")
    assert lines[1].startswith(f"::warning file={files['warn']},line=2,col=6,")
    assert "title=W504::" in lines[1]


def test_warnings_exit_0_unless_warnings_as_errors(files: dict[str, Path],
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(files["warn"])]) == 0
    assert "1 file checked: 0 errors, 1 warning" in capsys.readouterr().out
    assert main(["check", "--warnings-as-errors", str(files["warn"])]) == 1


def test_directory_is_searched_recursively(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    nested = tmp_path / "a" / "b"
    nested.mkdir(parents=True)
    (nested / "one.rdcd").write_text((EXAMPLES / "snake_wave.rdcd").read_text(), encoding="utf-8")
    (tmp_path / "two.rdcd").write_text(WARN, encoding="utf-8")
    (tmp_path / "notes.txt").write_text("not rdcd", encoding="utf-8")
    assert main(["check", str(tmp_path)]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "2 files checked: 0 errors, 1 warning"


def test_packet_budget_option(files: dict[str, Path], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", "--packet-budget", "64", str(EXAMPLES / "snake_wave.rdcd")]) == 0
    assert main(["check", "--packet-budget", "3", str(EXAMPLES / "snake_wave.rdcd")]) == 2
    assert "--packet-budget" in capsys.readouterr().err


@pytest.mark.parametrize("kind", ["missing", "empty_dir", "not_utf8"])
def test_io_errors_exit_2_with_one_line(tmp_path: Path, kind: str) -> None:
    if kind == "missing":
        target = tmp_path / "nope.rdcd"
    elif kind == "empty_dir":
        target = tmp_path
    else:
        target = tmp_path / "latin1.rdcd"
        target.write_bytes("role \xc4 { }".encode("latin-1"))
    done = _run(str(target))
    assert done.returncode == 2
    assert done.stdout == ""
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr
    assert done.stderr.startswith("rdcd check: ")


def test_unreadable_file_exit_2_in_process(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    directory = tmp_path / "dir.rdcd"
    directory.mkdir()
    (tmp_path / "x.rdcd").mkdir()
    assert main(["check", str(tmp_path / "x.rdcd" / "missing.rdcd")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_usage_error_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(["check", "--format", "xml", "a.rdcd"])
    assert exit_info.value.code == 2
    with pytest.raises(SystemExit) as exit_info:
        main(["check"])
    assert exit_info.value.code == 2
