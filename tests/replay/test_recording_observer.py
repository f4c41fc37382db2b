"""The recording watches the VM through ``vm.observer`` only: no runtime method is replaced, and the
first run of every slot is recorded, however often the memory of freed slots is reused."""

from __future__ import annotations

from sim.config import load_config
from sim.replay.recording import Recording
from sim.replay.sources import SourceIndex
from tests.replay.helpers import SOURCE, recorded_run
from tests.sim.helpers import obstacle_program
from tests.vm.vm_fakes import FakeHal
from vm.isa.assembler import assemble
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime


def test_the_recording_replaces_no_runtime_method() -> None:
    recording, _ = recorded_run("lattice", 2.0)
    assert recording.runtimes
    for runtime in recording.runtimes.values():
        assert runtime.observer is not None
        assert not {"_finish", "send_command", "handle_event", "install_command"} & set(vars(runtime))
        assert "Recording" not in runtime.on_event.__qualname__  # the report's own hook, untouched


def test_every_slots_first_run_is_recorded_though_freed_slots_are_recycled() -> None:
    program = obstacle_program()
    recording = Recording(load_config("car7"), SourceIndex(program, SOURCE), 10.0)
    vm = ModuleRuntime(FakeHal(), RoleTable({1: "Wheel"}, {}), module_id=0)
    recording._attach_runtimes({0: vm}, lambda: 0.0)
    code = assemble("NOP\nEND_TERMINATE")
    for _ in range(200):  # each a new program (a new id): a new slot, run once and freed
        vm.inject(code)
        vm.step()
    assert vm.programs_run == 200 and vm.store.slots == []
    assert sum(event[2] == "run" for event in recording.events) == 200
    watcher = vm.observer
    assert watcher is not None and len(watcher.ran) <= 64  # freed slots are not kept for ever
