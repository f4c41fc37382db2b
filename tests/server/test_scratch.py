"""``server.scratch``: what the server keeps for the editor, per document and per kind."""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

from server import scratch


@pytest.fixture()
def own_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    scratch.remove()
    yield tmp_path
    scratch.remove()


def made(kind: str, text: str) -> Path:
    work = scratch.work_folder()
    path = work / f"{kind}.out"
    path.write_text(text)
    return path


def test_the_newest_plot_and_replay_of_each_document(own_tmp: Path) -> None:
    plot = scratch.keep("file:///a.rdcd", "plot", made("plot", "p1"))
    replay = scratch.keep("file:///a.rdcd", "replay", made("replay", "r1"))
    assert plot.suffix == ".png" and replay.suffix == ".html"
    assert plot.parent == replay.parent == scratch.folder()
    assert replay.read_text() == "r1"
    newer = scratch.keep("file:///a.rdcd", "replay", made("replay", "r2"))
    assert not replay.exists() and newer.read_text() == "r2"
    assert plot.exists(), "a newer replay leaves the plot of the same document"
    other = scratch.keep("file:///b.rdcd", "replay", made("replay", "b"))
    assert other.exists() and newer.exists(), "another document's replay leaves this one's"


def test_at_most_max_plots_of_each_kind(own_tmp: Path) -> None:
    kept = {kind: [scratch.keep(f"file:///{i}.rdcd", kind, made(kind, str(i)))
                   for i in range(scratch.MAX_PLOTS + 2)] for kind in scratch.SUFFIXES}
    for files in kept.values():
        assert [f.exists() for f in files] == [False, False] + [True] * scratch.MAX_PLOTS  # the oldest go
    assert len(list(scratch.folder().glob("replay-*.html"))) == scratch.MAX_PLOTS
    assert len(list(scratch.folder().glob("plot-*.png"))) == scratch.MAX_PLOTS
