"""A command the entry module's startup sends before the command's code has diffused (issue 25):
held until the code is there on the default target, so the car moves; W606 on the original target,
whose firmware drops it."""

from __future__ import annotations

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm.lattice.world import LatticeWorld

CAR = """abstract role Wheel {
  abstract constant side;
  self.center_position == EAST_WEST;
  sizeof(self.total_connected()) == 1;
  sizeof(self.connected(UP)) == 1;
  sizeof(self.connected(side)) == 1;
  command go(speed) { self.turnContinuously(speed); }
}
role RightWheel extends Wheel { constant side := EAST; }
role LeftWheel extends Wheel { constant side := WEST; }
role Driver {
  self.center_position == NORTH_SOUTH;
  startup begin() { self.sleep(); self.sleep(); Wheel.go(2); }
}
deployment { Driver, RightWheel, LeftWheel }
"""


ISSUE_STARTUP = "self.sleep(); self.sleep(); Wheel.go(2);"  # the issue's: 2 s may or may not be enough


@pytest.mark.parametrize("startup", [ISSUE_STARTUP, "Wheel.go(2);"])
@pytest.mark.parametrize("loss", [0.0, 0.1])
def test_the_car_moves_when_its_entry_startup_sends_go(loss, startup):
    """With the go command's code in the wheels' discovery fragment (runtime arguments made it small),
    the issue's two seconds of sleep are enough for the code; sent at once, the command reaches the
    wheels before their code and is held."""
    text = CAR.replace(ISSUE_STARTUP, startup)
    result = check_text(text)
    assert not result.has_errors and not [d for d in result.diagnostics if d.code == "W606"]
    program = compile_model(result.model, text=text)
    structure = load_config("car7")
    world = LatticeWorld(structure, role_table(program), seed=11, packet_loss=loss)
    for name in program.injection:  # back to back, as rdcd simulate does
        world.inject(program.fragment(name).code)
    world.advance(20.0)
    assert world.roles_by_name()[structure.entry] == "Driver"
    wheels = [m for m, role in world.roles_by_name().items() if role and role.endswith("Wheel")]
    assert len(wheels) == 4
    for m in wheels:
        before = world.hals[m].joint_angle_deg()
        world.advance(0.1)
        assert world.hals[m].joint_angle_deg() != before  # turning
    if startup != ISSUE_STARTUP:
        assert sum(world.runtimes[m].held.released for m in wheels) >= 1  # it came before its code
    assert all(not state.errors for state in world.states())


def test_the_original_target_warns_on_that_line():
    diagnostics = check_text(CAR, target="original").diagnostics
    early = [d for d in diagnostics if d.code == "W606"]
    assert len(early) == 1
    assert CAR[early[0].span.start:].startswith("Wheel.go(2)")
    assert "RightWheel" in early[0].message and "LeftWheel" in early[0].message


def test_no_warning_when_the_code_is_injected_first():
    text = CAR.replace("deployment { Driver, RightWheel, LeftWheel }",
                       "deployment { RightWheel, LeftWheel, Driver }")
    assert not [d for d in check_text(text, target="original").diagnostics if d.code == "W606"]
