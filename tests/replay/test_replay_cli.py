"""``rdcd simulate --replay``: through the real command line, with bad paths and odd programs."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.cli.helpers import assert_clean_failure, rdcd
from tests.conftest import EXAMPLES
from tests.replay.helpers import page_data

PROGRAM = str(EXAMPLES / "obstacle_avoidance.rdcd")
FAST = ("--world", "lattice", "--duration", "3")


def test_writes_the_page_and_says_so(tmp_path: Path) -> None:
    out = tmp_path / "run.html"
    done = rdcd("simulate", PROGRAM, *FAST, "--replay", str(out))
    assert done.returncode == 0, done.stderr
    assert f"replay: {out}" in done.stdout
    data = page_data(out.read_text(encoding="utf-8"))
    assert data["meta"]["world"] == "lattice" and data["meta"]["duration_s"] == 3
    assert sorted(os.listdir(tmp_path)) == ["run.html"]  # no temporary file left


def test_html_is_added_when_the_name_has_no_extension(tmp_path: Path) -> None:
    done = rdcd("simulate", PROGRAM, *FAST, "--replay", str(tmp_path / "run"))
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "run.html").is_file()


@pytest.mark.parametrize("name", ["run.txt", "run.gif", "run.json"])
def test_an_unknown_extension_is_refused_before_the_run(tmp_path: Path, name: str) -> None:
    done = rdcd("simulate", PROGRAM, *FAST, "--replay", str(tmp_path / name))
    assert_clean_failure(done, 2, "--replay", "unknown format", ".html")
    assert not list(tmp_path.iterdir())


def test_bad_places_are_refused_before_the_run(tmp_path: Path) -> None:
    for path, words in [(tmp_path / "missing" / "run.html", ["does not exist"]),
                        (tmp_path, ["--replay"]),
                        ("", ["--replay"])]:
        done = rdcd("simulate", PROGRAM, *FAST, "--replay", str(path))
        assert_clean_failure(done, 2, *words)


def test_the_program_is_never_overwritten(tmp_path: Path) -> None:
    program = tmp_path / "car.html"  # a program file that happens to end in .html
    program.write_text(Path(PROGRAM).read_text(encoding="utf-8"), encoding="utf-8")
    before = program.read_bytes()
    done = rdcd("simulate", str(program), *FAST, "--replay", str(program))
    assert_clean_failure(done, 2, "refusing to overwrite")
    link = tmp_path / "link.html"
    link.symlink_to(program)
    done = rdcd("simulate", str(program), *FAST, "--replay", str(link))
    assert_clean_failure(done, 2, "refusing to overwrite")
    assert program.read_bytes() == before


def test_replay_and_report_on_one_file_are_refused(tmp_path: Path) -> None:
    out = str(tmp_path / "x.html")
    done = rdcd("simulate", PROGRAM, *FAST, "--replay", out, "--plot", out.replace(".html", ".svg"),
                "--report", out)
    assert_clean_failure(done, 2, "name the same file")


def test_a_program_with_errors_writes_no_page(tmp_path: Path) -> None:
    bad = tmp_path / "bad.rdcd"
    bad.write_text("role A { startup s() { self.nothing(); } }\ndeployment { A }\n", encoding="utf-8")
    done = rdcd("simulate", str(bad), *FAST, "--replay", str(tmp_path / "r.html"))
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert not (tmp_path / "r.html").exists()


def test_odd_program_text_is_carried_as_text(tmp_path: Path) -> None:
    text = Path(PROGRAM).read_text(encoding="utf-8")
    hostile = ("// </script><script>window.pwned = 1</script> <!-- <img src=x onerror=alert(1)> "
               "&amp; \u2028 ]]>\n")
    program = tmp_path / "odd.rdcd"
    program.write_text(hostile + text, encoding="utf-8")
    out = tmp_path / "odd.html"
    done = rdcd("simulate", str(program), *FAST, "--replay", str(out))
    assert done.returncode == 0, done.stderr
    html = out.read_text(encoding="utf-8")
    assert html.count("<script") == 2 and html.count("</script>") == 2
    assert "<img" not in html
    assert page_data(html)["source"]["lines"][0] == hostile.rstrip("\n")


def test_the_report_is_the_same_with_and_without_a_replay(tmp_path: Path) -> None:
    import json

    rdcd("simulate", PROGRAM, *FAST, "--report", str(tmp_path / "a.json"))
    rdcd("simulate", PROGRAM, *FAST, "--report", str(tmp_path / "b.json"),
         "--replay", str(tmp_path / "b.html"))
    a, b = (json.loads((tmp_path / n).read_text()) for n in ("a.json", "b.json"))
    for report in (a, b):
        report.pop("wall_time_s"), report.pop("real_time_factor")
    assert a == b


@pytest.mark.slow
def test_a_long_run_is_sampled_less_often_with_a_note(tmp_path: Path) -> None:
    out = tmp_path / "long.html"
    done = rdcd("simulate", PROGRAM, "--world", "lattice", "--config", "car17-wide", "--obstacle", "none",
                "--duration", "3600", "--replay", str(out), timeout=900)
    assert done.returncode == 0, done.stderr
    assert "note: long run: poses sampled every" in done.stdout
    data = page_data(out.read_text(encoding="utf-8"))
    assert data["meta"]["sample_hz"] < 10 and data["meta"]["notes"]
    assert out.stat().st_size < 20_000_000
