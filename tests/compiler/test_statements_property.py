"""Property: any checked program of random statements compiles to fragments that pass the
verifier, fit the slot or are reported, and keep the stack balanced (no crash, no exception)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from tests.syntax.fuzz_inputs import nested_statements
from vm.isa.targets import ORIGINAL
from vm.isa.verifier import verify

CONDITIONS = ["self.y() > 0", "self.x() == 2", "connected_role(DOWN, W) > 0", "!(self.z() < -1)",
              "sizeof(self.connected(UP)) >= 1 && self.y() != 3", "sizeof(connected_role(EAST, M)) == 0",
              "self.center_position == UP_DOWN || self.x() <= k"]
SIMPLE = ["self.setLed(k);", "self.sleep();", "self.turnTowards(-30);", "self.turnContinuously(-k);",
          "self.stopTurning();", "self.sleepWhileTurning(2);", "W.ping();", "self.helper();",
          "self.disableEvent(EVENT_PROXIMITY_2);", "self.turnDegrees(90);", ";"]


def statements(depth: int) -> st.SearchStrategy[str]:
    return nested_statements(SIMPLE, CONDITIONS, depth, ("self.handleEvent(EVENT_PROXIMITY_4, {{ {body} }});",
                                                          "self.assumeRole(M, {{ {body} }});"))


def program(startup: str, behaviour: str, command: str) -> str:
    return (
        "abstract role W { abstract constant k; self.center_position == EAST_WEST;\n"
        f"  startup s() {{ {startup} }}\n  behavior b() {{ {behaviour} }}\n"
        f"  command ping() {{ {command} }}\n  helper() {{ self.setLed(3); }} }}\n"
        "role A extends W { constant k := 2; self.y() > 0; }\n"
        "role B extends W { constant k := 5; self.y() < 0; }\n"
        "role M modifies W { }\n"
        "role C { connected_role(UP, W) > 0; }\n"
        "deployment { A, B, C }\n")


body = st.lists(statements(2), max_size=4).map(" ".join)


@settings(max_examples=60)
@given(body, body, body, st.sampled_from([30, 50, 71]))
def test_random_statements_compile_to_verified_fragments(startup, behaviour, command, budget):
    text = program(startup, behaviour, command)
    result = check_text(text, packet_budget=budget)
    if result.has_errors:
        return
    compiled = compile_model(result.model, packet_budget=budget, strict_isa=True, text=text)
    assert not any(d.code in ("E607", "E608") for d in compiled.diagnostics)
    refused = any(d.code == "E605" for d in compiled.diagnostics)  # what the firmware cannot run
    for fragment in compiled.fragments:
        if fragment.size <= 64:
            assert verify(fragment.code, strict=True) == [], fragment.name
            if not refused:  # the original target: only its opcodes, stack 5, 100 steps
                assert verify(fragment.code, target=ORIGINAL) == [], fragment.name
        if fragment.size > budget - 7:
            assert any(d.code in ("W601", "E601") for d in compiled.diagnostics)
