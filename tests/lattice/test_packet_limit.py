"""The worlds enforce the IR packet limit as the ATRON does: a packet over 50 bytes is not sent,
and the run's report and summary say so (issue 25)."""

from __future__ import annotations

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.report import summary
from sim.run import Options, role_table, simulate
from tests.conftest import EXAMPLES
from vm.lattice.world import LatticeWorld

LEDS = " ".join(f"self.setLed({i});" for i in range(19))
# one statement that cannot be split (the condition reads a neighbour's role): W601
OVER = (f"role A {{ self.center_position == EAST_WEST;\n  startup s() {{ if (connected_role(UP, A) > 0) "
        f"{{ {LEDS} }} }} }}\nrole B {{ self.center_position != EAST_WEST; }}\ndeployment {{ B, A }}\n")


def program():
    result = check_text(OVER)
    (warning,) = [d for d in result.diagnostics if d.code == "W601"]
    assert "would not receive" in warning.message
    return compile_model(result.model, text=OVER)


def test_a_packet_over_the_limit_is_not_sent():
    compiled = program()
    structure = load_config("car7")
    world = LatticeWorld(structure, role_table(compiled), seed=1)
    seen = []
    world.network.on_oversize = lambda now, source, physical, packet: seen.append(len(packet))
    for name in compiled.injection:
        world.inject(compiled.fragment(name).code)
    world.advance(5.0)
    assert world.counters.oversize > 0 and all(n > 50 for n in seen)
    big = next(f for f in compiled.fragments if f.size > compiled.program_budget)
    for mid, runtime in world.runtimes.items():
        if mid != structure.entry:  # only the entry module, where it is injected, has it
            assert all(slot.code != big.code for slot in runtime.store.slots)


def test_the_report_and_summary_say_so():
    report = simulate(program(), load_config("car7"), Options(world="lattice", config="car7", duration=5.0))
    events = [e for e in report["events"] if e["kind"] == "packet_not_sent"]
    assert events and events[0]["detail"]["bytes"] > 50 and events[0]["detail"]["type"] == "program"
    assert report["messages"]["not_sent_over_limit"] >= len(events)
    assert "over the 50-byte IR packet limit" in summary(report)


def test_programs_that_fit_send_everything():
    text = (EXAMPLES / "obstacle_avoidance.rdcd").read_text(encoding="utf-8")
    compiled = compile_model(check_text(text).model, text=text)
    report = simulate(compiled, load_config("car7"), Options(world="lattice", config="car7", duration=5.0))
    assert report["messages"]["not_sent_over_limit"] == 0
    assert "IR packet limit" not in summary(report)
