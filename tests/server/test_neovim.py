"""rdcd-lsp under a real second client: a headless Neovim (0.7+, Debian's package; installed in CI
by ``.ci/neovim.sh``) runs ``tests/server/nvim/lsp_session.lua``, which starts the server with
``vim.lsp.start_client`` on a copy of an example with one unknown name, asks for hover and
completion, fixes the name through buffer edits and writes what it saw as JSON."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from tests.server.conftest import EXAMPLES, ROOT

NVIM = shutil.which("nvim")
SCRIPT = Path(__file__).resolve().parent / "nvim" / "lsp_session.lua"
MARKER = "    self.turnContinuously(turn_direction);\n  }\n  command"
TYPO = "turn_directon"  # an unknown name, one letter short of the constant turn_direction
WAIT_MS = 8000  # bound of every single wait inside Neovim
PROCESS_TIMEOUT = 28  # seconds for the whole Neovim run, server included

pytestmark = pytest.mark.skipif(NVIM is None, reason="nvim is not on PATH (.ci/neovim.sh installs it)")


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    assert NVIM is not None
    tmp = tmp_path_factory.mktemp("nvim")
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()
    assert MARKER in text
    program = tmp / "obstacle_avoidance.rdcd"
    program.write_text(text.replace(MARKER, MARKER.replace("turn_direction", TYPO, 1), 1))
    result = tmp / "result.json"
    env = dict(os.environ,
               RDCD_NVIM_FILE=str(program), RDCD_NVIM_OUT=str(result), RDCD_NVIM_PYTHON=sys.executable,
               RDCD_NVIM_ROOT=str(ROOT), RDCD_NVIM_TIMEOUT_MS=str(WAIT_MS),
               # keep Neovim's state, cache (lsp.log) and data out of the real home
               XDG_CONFIG_HOME=str(tmp / "config"), XDG_DATA_HOME=str(tmp / "data"),
               XDG_STATE_HOME=str(tmp / "state"), XDG_CACHE_HOME=str(tmp / "cache"))
    command = [NVIM, "--headless", "--clean", "-u", "NONE", "-n", "-i", "NONE",
               "-c", f"luafile {SCRIPT}"]
    started = time.monotonic()
    # own session: on a timeout the whole group (Neovim and the server it started) is killed
    process = subprocess.Popen(command, cwd=str(tmp), env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        stdout, stderr = process.communicate(timeout=PROCESS_TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        _, stderr = process.communicate()
        pytest.fail(f"nvim did not finish within {PROCESS_TIMEOUT} s; "
                    f"stderr: {stderr.decode(errors='replace')}")
    elapsed = time.monotonic() - started
    log = (f"exit {process.returncode}\nstdout: {stdout.decode(errors='replace')}"
           f"\nstderr: {stderr.decode(errors='replace')}")
    assert result.exists(), f"nvim wrote no result; {log}"
    observed = json.loads(result.read_text())
    assert "error" not in observed, f"{observed['error']}\nsteps: {observed.get('steps')}\n{log}"
    assert process.returncode == 0, log
    observed["elapsed"] = elapsed
    return observed


def test_runs_to_the_end_quickly(session: dict[str, Any]) -> None:
    assert session["steps"] == ["opened", "initialized", "diagnostics", "hover", "completion", "fixed",
                                "stopped"]
    assert session["filetype"] == "rdcd"
    assert session["stopped"] is True, "the server did not exit after shutdown"
    assert session["elapsed"] < PROCESS_TIMEOUT


def test_diagnostic_for_the_unknown_name(session: dict[str, Any]) -> None:
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()
    line = text[:text.index(MARKER)].count("\n")  # 0-based line of the typo
    column = MARKER.index("turn_direction")
    [diagnostic] = session["diagnostics"]
    assert diagnostic["code"] == "E201" and diagnostic["source"] == "rdcd" and diagnostic["severity"] == 1
    assert (diagnostic["line"], diagnostic["character"]) == (line, column)
    assert TYPO in diagnostic["message"] and "turn_direction" in diagnostic["message"]
    # Neovim's own diagnostic store has it as well (0-based lnum/col)
    [stored] = session["vim_diagnostics"]
    assert (stored["lnum"], stored["col"], stored["code"]) == (line, column, "E201")


def test_hover_on_a_role(session: dict[str, Any]) -> None:
    hover = session["hover"]
    assert isinstance(hover, dict) and hover["kind"] == "markdown"
    value = hover["value"]
    assert "role" in value and "RightWheel" in value and "Wheel" in value
    assert "turn_direction" in value


def test_completion_after_self(session: dict[str, Any]) -> None:
    labels = set(session["completion"])
    assert {"turnContinuously", "turnTowards", "handleEvent", "assumeRole", "center_position"} <= labels


def test_diagnostics_cleared_after_the_fix(session: dict[str, Any]) -> None:
    assert session["fixed_line"] == "    self.turnContinuously(turn_direction);"
    assert session["final_diagnostics"] == []
    assert session["final_vim_diagnostics"] == 0
    # the empty publish is for the buffer's current version, not a stale one
    assert session["final_version"] == session["buffer_version"]
    assert session["final_version"] > session["diagnostics_version"]
