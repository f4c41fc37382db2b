"""Driving the replay page in headless Chromium through tests/replay/probe.mjs (playwright-core).

Needs node, Chromium (``CHROMIUM`` or /usr/bin/chromium) and the viewer's node modules
(``npm ci`` in sim/replay/viewer). Without them the browser tests skip with the reason, unless
``RDCD_REPLAY_BROWSER=require`` (CI's sim/replay/viewer/ci.sh), where they fail.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import ROOT

VIEWER = ROOT / "sim" / "replay" / "viewer"
PROBE = Path(__file__).resolve().parent / "probe.mjs"


def missing() -> str | None:
    """Why the browser cannot be driven here, or None."""
    if shutil.which("node") is None:
        return "node is not installed"
    chromium = os.environ.get("CHROMIUM", "/usr/bin/chromium")
    if not os.access(chromium, os.X_OK):
        return f"Chromium is not installed at {chromium} (apt-get install chromium, or set CHROMIUM)"
    if not (VIEWER / "node_modules" / "playwright-core").is_dir():
        return "playwright-core is not installed (run `npm ci` in sim/replay/viewer)"
    return None


def need_browser() -> None:
    reason = missing()
    if reason is None:
        return
    if os.environ.get("RDCD_REPLAY_BROWSER") == "require":
        pytest.fail(f"RDCD_REPLAY_BROWSER=require but {reason}")
    pytest.skip(reason)


def probe(page: Path, timeout: float = 300, **options: Any) -> dict[str, Any]:
    env = {**os.environ, "RDCD_REPLAY_NODE_MODULES": str(VIEWER / "node_modules")}
    done = subprocess.run(["node", str(PROBE), str(page), json.dumps(options)], capture_output=True,
                          text=True, timeout=timeout, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout)
