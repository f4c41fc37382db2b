"""rdcd simulate --change / --changes: outside changes are checked before the run; every bad one
is one line on stderr and exit status 2, never a traceback."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli.helpers import assert_clean_failure, rdcd

PROGRAM = "examples/lose_a_wheel.rdcd"
LATTICE = ("--world", "lattice", "--duration", "30", "--obstacle", "none")


@pytest.mark.parametrize(("change", "words"), [
    ("20s:detach 33", ("no module 33",)),
    ("40s:detach 3", ("after the end of the run",)),
    ("1s:attach 9 at 0,0,0", ("taken by module 0",)),
    ("1s:attach 9 at 20,20,20", ("no free connector",)),
    ("1s:attach 9 at 1,0,0", ("not a lattice cell",)),
    ("1s:attach 9 at 2,0,-2 EW", ("has axis NS",)),
    ("1s:attach 3 at 2,0,-2", ("exists already",)),
    ("1s:detach 0", ("entry module",)),
    ("5s:detach 3\n6s:stop 3", ("detached before",)),
    ("1s:explode 3", ("unknown change",)),
    ("soon:detach 3", ("TIME:detach ID",)),
    ("1s:detach 99999999999999999999", ("TIME:detach ID",)),
    ("1s:attach 9 at 99999,0,0", ("TIME:detach ID",)),
    ("1s:stop 3 at 1,1,0", ("takes only a module id",)),
])
def test_bad_changes_are_refused_before_the_run(change: str, words: tuple[str, ...]) -> None:
    args = []
    for line in change.splitlines():
        args += ["--change", line]
    assert_clean_failure(rdcd("simulate", PROGRAM, *LATTICE, *args), 2, *words)


def test_a_changes_file_and_its_bad_forms(tmp_path: Path) -> None:
    good = tmp_path / "changes.txt"
    good.write_text("# a person takes a wheel off\n20s:detach 3\n\n25:stop 5  # and stops another\n")
    report = tmp_path / "r.json"
    done = rdcd("simulate", PROGRAM, *LATTICE, "--changes", str(good), "--report", str(report))
    assert done.returncode == 0, done.stderr
    assert "structure: 2 outside changes" in done.stdout
    data = json.loads(report.read_text())
    assert [e["module"] for e in data["events"] if e["kind"] == "outside"] == [3, 5]
    assert {"final_lattice", "final_orientation", "final_mount"} <= set(data["modules"][0])
    assert data["connections"] and data["parts"] == [[0, 1, 2, 4, 5, 6]]
    assert_clean_failure(rdcd("simulate", PROGRAM, *LATTICE, "--changes", str(tmp_path)), 2)
    assert_clean_failure(rdcd("simulate", PROGRAM, *LATTICE, "--changes", str(tmp_path / "none")), 2)
    binary = tmp_path / "bin.txt"
    binary.write_bytes(b"\xff\xfe\x00")
    assert_clean_failure(rdcd("simulate", PROGRAM, *LATTICE, "--changes", str(binary)), 2, "UTF-8")
    huge = tmp_path / "huge.txt"
    huge.write_text("1s:stop 3\n" * 200_000)
    assert_clean_failure(rdcd("simulate", PROGRAM, *LATTICE, "--changes", str(huge)), 2, "1 MB")
    many = tmp_path / "many.txt"
    many.write_text("1s:stop 3\n" * 1001)
    assert_clean_failure(rdcd("simulate", PROGRAM, *LATTICE, "--changes", str(many)), 2, "at most 1000")
