"""The documentation site, built with `mkdocs build --strict`, in real headless Chromium: every
page loads over http without an error in the console, a failed request or a request to another
host (the site reads offline), the site's search finds "assumeRole" (MkDocs' search needs http:
its index is fetched by a web worker), and the State page's RDCD is coloured (its keywords drawn
in another colour than plain text: pymdownx.highlight with rdcd_core/pygments_lexer.py).

Needs mkdocs (pip install -e '.[docs]'), node, Chromium and playwright-core (the replay viewer's
node modules, `npm ci` in sim/replay/viewer). Without them it skips with the reason, unless
RDCD_DOCS_BROWSER=require (CI), where it fails.
"""

from __future__ import annotations

import functools
import http.server
import json
import os
import shutil
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import ROOT
from tests.replay.browser import VIEWER
from tests.replay.browser import missing as browser_missing

PROBE = Path(__file__).resolve().parent / "site_probe.mjs"


def _need() -> None:
    reason = browser_missing()
    if reason is None and shutil.which("mkdocs") is None and not _has_mkdocs():
        reason = "mkdocs is not installed (pip install -e '.[docs]')"
    if reason is None:
        return
    if os.environ.get("RDCD_DOCS_BROWSER") == "require":
        pytest.fail(f"RDCD_DOCS_BROWSER=require but {reason}")
    pytest.skip(reason)


def _has_mkdocs() -> bool:
    import importlib.util

    return importlib.util.find_spec("mkdocs") is not None


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, list[str]]]:
    """The built site served on 127.0.0.1: (base URL, every page's path)."""
    _need()
    folder = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet", "-d", str(folder)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    pages = sorted(str(p.relative_to(folder)) for p in folder.rglob("index.html"))
    handler = functools.partial(_Quiet, directory=str(folder))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/", pages
    finally:
        server.shutdown()
        server.server_close()


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:  # noqa: A002 - the base class's name
        pass


def _probe(base: str, pages: list[str], query: str, highlight_page: str = "") -> dict:
    env = {**os.environ, "RDCD_NODE_MODULES": str(VIEWER / "node_modules")}
    done = subprocess.run(["node", str(PROBE), base, json.dumps(pages), query, highlight_page],
                          capture_output=True, text=True, timeout=600, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout)


@pytest.fixture(scope="module")
def probed(site: tuple[str, list[str]]) -> dict:
    """One pass of the browser over the whole site (it is slow): pages, search, the State page's colours."""
    base, pages = site
    return _probe(base, pages, "assumeRole", "state/index.html")


def test_every_page_loads_cleanly_and_search_finds_assume_role(site: tuple[str, list[str]],
                                                               probed: dict) -> None:
    _, pages = site
    names = ("getting-started", "tutorial", "language", "module-api", "diagnostics", "vm", "instructions",
             "cli", "simulator", "sweeps", "replay", "editor", "architecture", "benchmarks")
    expected = {"index.html", *(f"{name}/index.html" for name in names)}
    assert expected <= set(pages)
    result = probed
    for page in pages:
        shown = result["pages"][page]
        assert shown["status"] == 200 and shown["errors"] == [], (page, shown)
        assert shown["title"].endswith("rdcd"), (page, shown["title"])
    search = result["search"]
    assert search["errors"] == []
    count = int(search["meta"].split()[0])
    assert count >= 2, search["meta"]
    assert any("/language/" in href and "assumerole" in href for href in search["results"]), search["results"]


def test_the_rdcd_on_the_state_page_is_coloured(probed: dict) -> None:
    """The gradient on the State page: `state`, `role`, `behavior` and `deployment` are keyword spans
    (Pygments' k/kd classes) drawn in a colour of their own, and `self.x` a built-in."""
    shown = probed["highlight"]
    assert shown["blocks"] >= 1, shown
    plain = shown["plain"]
    keywords = {s["text"]: s["color"] for s in shown["spans"] if set(s["cls"].split()) & {"k", "kd"}}
    assert {"state", "role", "behavior", "deployment"} <= set(keywords), shown["spans"]
    assert all(color != plain for color in keywords.values()), (plain, keywords)
    builtins = {s["text"]: s["color"] for s in shown["spans"] if "nb" in s["cls"].split()}
    assert "x" in builtins and builtins["x"] != plain, (plain, builtins)
    assert not any("err" in s["cls"].split() for s in shown["spans"]), shown["spans"]


def test_a_page_that_is_missing_is_reported(site: tuple[str, list[str]]) -> None:
    """The probe can fail: a page that does not exist shows as a 404 with its failed request."""
    base, _ = site
    shown = _probe(base, ["no-such-page/index.html"], "assumeRole")["pages"]["no-such-page/index.html"]
    assert shown["status"] == 404 and shown["errors"]
