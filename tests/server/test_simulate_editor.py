"""``rdcd.simulate`` from the editor: the first error at the user's file and line, one clear error for
options no command line can carry, and no temporary folder left behind on any path. The server runs
with its own TMPDIR so that what it leaves there can be listed."""

from __future__ import annotations

import asyncio
import os
import signal
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException

from tests.server.conftest import EXAMPLES, Session

OBSTACLE = (EXAMPLES / "obstacle_avoidance.rdcd").read_text()
QUICK = {"config": "car7", "obstacle": "none", "duration": 1, "seed": 0, "world": "lattice"}
DEAD_PID = 99_999_999  # above any pid_max: no such process


class Simulating:
    def __init__(self, session: Session, tmp: Path, user: Path) -> None:
        self.session, self.tmp, self.user = session, tmp, user

    def run(self, uri: str, options: object, timeout: float = 120) -> dict:
        return self.session.run(self.start(uri, options), timeout=timeout)

    def start(self, uri: str, options: object) -> asyncio.Future:
        params = types.ExecuteCommandParams(command="rdcd.simulate", arguments=[uri, options])
        request = self.session.client.protocol.send_request_async(types.WORKSPACE_EXECUTE_COMMAND, params)
        return asyncio.ensure_future(request, loop=self.session.loop)

    def refusal(self, uri: str, options: object) -> JsonRpcException:
        with pytest.raises(JsonRpcException) as caught:
            self.run(uri, options)
        return caught.value

    def server_folders(self) -> list[Path]:
        return [p for p in self.tmp.iterdir() if p.name.startswith(f"rdcd-lsp-{self.pid()}-")]

    def pid(self) -> int:
        return self.session.client._server.pid  # type: ignore[attr-defined]

    def leftovers(self) -> list[Path]:
        """Anything of the server's in TMPDIR but the plots kept in its own folder."""
        found = [p for p in self.tmp.iterdir()
                 if p.name.startswith("rdcd") and not p.name.startswith("rdcd-lsp-")]
        for folder in self.server_folders():
            found += [p for p in folder.iterdir() if not p.name.startswith("plot-")]
        return found


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Simulating]:
    tmp = tmp_path_factory.mktemp("server-tmp")
    user = tmp_path_factory.mktemp("user files")
    (tmp / f"rdcd-lsp-{DEAD_PID}-orphan").mkdir()
    (tmp / f"rdcd-lsp-{DEAD_PID}-orphan" / "plot-old.png").write_bytes(b"x")
    (tmp / f"rdcd-lsp-{os.getpid()}-alive").mkdir()  # a running process's: kept
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("TMPDIR", str(tmp))
        session = Session()
    simulating = Simulating(session, tmp, user)
    pid = simulating.pid()
    yield simulating
    session.close()
    assert not list(tmp.glob(f"rdcd-lsp-{pid}-*")), "the server's folder is removed when it exits"


def user_file(sim: Simulating, name: str, text: str, open_it: bool = True) -> tuple[str, Path]:
    path = sim.user / name
    path.write_text(text)
    uri = path.as_uri()
    if open_it:
        sim.session.open(uri, text)
    return uri, path


def test_first_error_at_the_users_file_and_line(sim: Simulating) -> None:
    uri, path = user_file(sim, "two errors.rdcd", "role A {\n  x := 1\n}\nrole A { }\nbroken\n")
    error = sim.refusal(uri, QUICK)
    assert error.message.startswith(f"{path}:2:"), error.message
    assert "error[" in error.message
    assert "simulation failed" not in error.message and "note" not in error.message
    assert "rdcd-lsp-" not in error.message and "\n" not in error.message
    assert not sim.leftovers()


def test_an_error_with_a_related_note_shows_the_error(sim: Simulating) -> None:
    uri, path = user_file(sim, "dup.rdcd", "role A { }\nrole A { }\ndeployment { A }\n")
    error = sim.refusal(uri, QUICK)
    assert error.message.startswith(f"{path}:2:6: error[E101]:"), error.message
    assert "note" not in error.message


def test_a_file_that_is_not_open(sim: Simulating) -> None:
    uri, path = user_file(sim, "closed.rdcd", "role A {\n\n  y = ;\n}\n", open_it=False)
    error = sim.refusal(uri, QUICK)
    assert error.message.startswith(f"{path}:3:"), error.message


def test_a_failure_of_the_simulator_names_no_temporary_path(sim: Simulating) -> None:
    uri, _ = user_file(sim, "fine.rdcd", OBSTACLE)
    for options, expected in [({**QUICK, "config": "no-such-config"}, "no-such-config"),
                              ({**QUICK, "duration": 99_999}, "--duration"),
                              ({**QUICK, "config": "--gui"}, "--gui"),
                              ({**QUICK, "world": "mars"}, "mars")]:
        error = sim.refusal(uri, options)
        assert error.message.startswith("rdcd simulate:") and expected in error.message, error.message
        assert "rdcd-lsp-" not in error.message and "simulation failed" not in error.message
    assert not sim.leftovers()


BAD_VALUES = ["car\x007", "\x00", "wall:1\n--gui", "\ud800", "a\u2028b", "x" * 5000, [1], {"a": 1}, True]


@pytest.mark.parametrize("key", ["config", "obstacle", "duration", "seed", "world", "packetLoss"])
def test_options_no_command_line_can_carry(sim: Simulating, key: str) -> None:
    uri, _ = user_file(sim, "options.rdcd", OBSTACLE)
    for value in BAD_VALUES:
        error = sim.refusal(uri, {**QUICK, key: value})
        assert error.code == -32803, error
        assert key in error.message and "\n" not in error.message, error.message
        assert "Traceback" not in error.message
    assert "U+0000" in sim.refusal(uri, {**QUICK, key: "\x00"}).message
    assert not sim.leftovers()


def test_options_that_are_not_options(sim: Simulating) -> None:
    uri, _ = user_file(sim, "not-options.rdcd", OBSTACLE)
    assert "unknown simulate option" in sim.refusal(uri, {**QUICK, "duraton": 5}).message
    assert "object" in sim.refusal(uri, [1, 2]).message
    assert not sim.leftovers()


def test_a_document_uri_with_a_nul(sim: Simulating) -> None:
    error = sim.refusal("file:///tmp/a\x00b.rdcd", QUICK)
    assert error.code == -32803
    assert not sim.leftovers()


def test_success_keeps_only_the_plot_and_replaces_it(sim: Simulating) -> None:
    uri, _ = user_file(sim, "plotted.rdcd", OBSTACLE)
    first = Path(sim.run(uri, QUICK)["plotPath"])
    assert first.is_file() and first.parent in sim.server_folders()
    assert not sim.leftovers()  # the program copy, the report and the working folder are gone
    assert not (sim.tmp / f"rdcd-lsp-{DEAD_PID}-orphan").exists(), "a killed server's folder is removed"
    assert (sim.tmp / f"rdcd-lsp-{os.getpid()}-alive").exists(), "a running server's folder is kept"
    second = Path(sim.run(uri, QUICK)["plotPath"])
    assert second.is_file() and not first.exists()  # the newer plot of the same document replaces it
    assert not sim.leftovers()


def test_cancellation_leaves_nothing(sim: Simulating) -> None:
    uri, _ = user_file(sim, "cancelled.rdcd", OBSTACLE)
    before = set(sim.session.client.progress_reports)
    running = sim.start(uri, {"config": "car7", "duration": 3600, "seed": 0, "world": "lattice"})

    async def cancel_when_started() -> None:
        while not set(sim.session.client.progress_reports) - before:
            await asyncio.sleep(0.05)
        await asyncio.sleep(0.3)
        token = (set(sim.session.client.progress_reports) - before).pop()
        sim.session.client.window_work_done_progress_cancel(types.WorkDoneProgressCancelParams(token=token))

    sim.session.run(cancel_when_started(), timeout=60)
    with pytest.raises(JsonRpcException) as caught:
        sim.session.run(running, timeout=30)
    assert "cancel" in caught.value.message
    assert not sim.leftovers()


def _children_of_folder(folder: Path) -> list[str]:
    """Command lines of running processes that name ``folder`` (a simulator child left running)."""
    found = []
    for proc in Path("/proc").iterdir():
        try:
            cmdline = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode("utf-8", "replace")
        except OSError:
            continue
        if proc.name.isdigit() and str(folder) in cmdline:
            found.append(cmdline)
    return found


@pytest.mark.skipif(not Path("/proc/self/cmdline").exists(), reason="lists processes through /proc")
@pytest.mark.parametrize("ending", ["sigterm", "end of input", "exit"])
def test_a_server_that_ends_mid_simulation_leaves_nothing(tmp_path: Path, ending: str) -> None:
    """The running child is killed and the server's folder removed, however the server is ended."""
    from tests.server.rawclient import RawServer, notification, request

    server = RawServer(env=dict(os.environ, TMPDIR=str(tmp_path)))
    try:
        server.initialize()
        uri = (tmp_path / "long.rdcd").as_uri()
        server.send(notification("textDocument/didOpen", {"textDocument": {
            "uri": uri, "languageId": "rdcd", "version": 1, "text": OBSTACLE}}))
        server.send(request("sim", "workspace/executeCommand", {"command": "rdcd.simulate", "arguments": [
            uri, {"config": "car7", "duration": 3600, "world": "lattice"}]}))
        deadline = time.monotonic() + 60
        while not _children_of_folder(tmp_path):  # the simulator child runs
            assert time.monotonic() < deadline, "no simulation started"
            time.sleep(0.05)
        if ending == "sigterm":
            server.process.send_signal(signal.SIGTERM)
            assert server.wait() == 128 + signal.SIGTERM
        elif ending == "end of input":
            assert server.process.stdin is not None
            server.process.stdin.close()
            assert server.wait() == 1
        else:
            server.send(notification("exit"))
            assert server.wait() == 1
    finally:
        server.kill()
    assert not list(tmp_path.glob("rdcd-lsp-*")), "the server's folder is removed"
    assert not _children_of_folder(tmp_path), "the simulator child is not left running"
    assert "Traceback" not in server.stderr_text()


def test_a_relative_configuration_file_is_read_beside_the_document(sim: Simulating) -> None:
    from tests.server.conftest import ROOT

    (sim.user / "configs").mkdir(exist_ok=True)
    (sim.user / "configs" / "my-car.json").write_text((ROOT / "sim" / "configs" / "car7.json").read_text())
    uri, _ = user_file(sim, "configured.rdcd", OBSTACLE)
    result = sim.run(uri, {**QUICK, "config": "configs/my-car.json"})
    assert result["report"]["modules"]
    assert not sim.leftovers()
