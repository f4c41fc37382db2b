"""The documentation site, built with `mkdocs build --strict`, in real headless Chromium: every
page loads over http without an error in the console or a failed request, and the site's search
finds "assumeRole" (MkDocs' search needs http: its index is fetched by a web worker).

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


def _probe(base: str, pages: list[str], query: str) -> dict:
    env = {**os.environ, "RDCD_NODE_MODULES": str(VIEWER / "node_modules")}
    done = subprocess.run(["node", str(PROBE), base, json.dumps(pages), query], capture_output=True,
                          text=True,
                          timeout=600, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout)


def test_every_page_loads_cleanly_and_search_finds_assume_role(site: tuple[str, list[str]]) -> None:
    base, pages = site
    names = ("getting-started", "tutorial", "language", "module-api", "diagnostics", "vm", "instructions",
             "cli", "simulator", "sweeps", "replay", "editor", "architecture", "benchmarks")
    expected = {"index.html", *(f"{name}/index.html" for name in names)}
    assert expected <= set(pages)
    result = _probe(base, pages, "assumeRole")
    for page in pages:
        shown = result["pages"][page]
        assert shown["status"] == 200 and shown["errors"] == [], (page, shown)
        assert shown["title"].endswith("rdcd"), (page, shown["title"])
    search = result["search"]
    assert search["errors"] == []
    count = int(search["meta"].split()[0])
    assert count >= 2, search["meta"]
    assert any("/language/" in href and "assumerole" in href for href in search["results"]), search["results"]


def test_a_page_that_is_missing_is_reported(site: tuple[str, list[str]]) -> None:
    """The probe can fail: a page that does not exist shows as a 404 with its failed request."""
    base, _ = site
    shown = _probe(base, ["no-such-page/index.html"], "assumeRole")["pages"]["no-such-page/index.html"]
    assert shown["status"] == 404 and shown["errors"]
