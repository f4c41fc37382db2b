"""Commands and behaviours too large for one fragment become chains of commands that fit
(rdcd_core/compiler/chain.py), and run as the unsplit code would, under loss too."""

from __future__ import annotations

import pytest

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from sim.config import load_config
from sim.run import role_table
from vm.lattice.world import LatticeWorld

WHEELS = """abstract role Wheel {{
  abstract constant side;
  state told := 0;
  self.center_position == EAST_WEST;
  sizeof(self.total_connected()) == 1;
  sizeof(self.connected(side)) == 1;
  {member}
}}
role RightWheel extends Wheel {{ constant side := EAST; }}
role LeftWheel extends Wheel {{ constant side := WEST; }}
role Driver {{
  self.center_position == NORTH_SOUTH;
  startup begin() {{ Wheel.{call}; }}
}}
deployment {{ Driver, RightWheel, LeftWheel }}
"""
SHOW = ("command show(v) {\n    self.setLed(v); self.sleep(); self.setLed(1); self.turnTowards(30);\n"
        "    self.sleep(); self.setLed(2); self.turnTowards(-30); self.sleep(); self.setLed(3);\n"
        "    self.turnTowards(0); self.sleep(); self.setLed(4); self.turnTowards(90); self.sleep();\n"
        "    self.setLed(0); told := told + v; }")
GAIT = ("behavior b() { told := told + 1; self.setLed(told); self.turnTowards(30); self.sleep();\n"
        "    self.setLed(1); self.turnTowards(-30); self.sleep(); self.setLed(2); self.turnTowards(0);\n"
        "    self.sleep(); self.setLed(3); self.turnTowards(60); self.sleep(); }\n"
        "  command noop() { }")


def compiled(text: str, target: str = "default"):
    result = check_text(text, target=target)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    return result, compile_model(result.model, text=text, target=target)


def test_a_long_command_is_a_chain_of_fragments_that_fit():
    result, program = compiled(WHEELS.format(member=SHOW, call="show(3)"))
    assert not [d for d in result.diagnostics if d.code in ("W601", "E601")]
    assert all(f.size <= program.program_budget for f in program.fragments)
    holding = [f for f in program.fragments if "show" in f.methods]
    assert len(holding) >= 3  # the parts of both wheels' chains (some share a fragment)


def test_a_long_behaviour_loops_through_its_chain():
    result, program = compiled(WHEELS.format(member=GAIT, call="noop()"))
    assert not [d for d in result.diagnostics if d.code in ("W601", "E601")]
    assert all(f.size <= program.program_budget for f in program.fragments)


def test_a_statement_too_large_alone_is_named_and_the_rest_fits():
    # one statement of 13 state reads and 12 additions: too large for a packet (not for a slot), whatever the
    # compiler does with runtime values
    sum_of_reads = " + ".join(["told"] * 13)
    member = ("command go(speed) { told := told + 1; self.setLed(told); self.turnContinuously(speed);\n"
              f"    self.sleep(); self.setLed(0); self.setLed({sum_of_reads}); self.sleep();\n"
              "    self.stopTurning(); }")
    text = WHEELS.format(member=member, call="go(2)")
    result = check_text(text)
    over = [d for d in result.diagnostics if d.code in ("W601", "E601")]
    assert over and all(d.code == "W601" for d in over)  # before splitting: E601, over a slot
    for d in over:
        assert text[d.span.start:].startswith(f"self.setLed({sum_of_reads})")
        assert "this statement alone" in d.message and "would not receive" in d.message
    program = result.compiled
    assert sum(f.size > program.program_budget for f in program.fragments) == len(over)


def test_existing_programs_do_not_split(example_programs):
    sizes = {name: [f.size for f in p.fragments] for name, p in example_programs.items()}
    assert sizes["obstacle_avoidance.rdcd"] and sum(sizes["obstacle_avoidance.rdcd"]) == 150


def test_no_spare_command_number_leaves_the_command_whole():
    commands = " ".join(f"command c{i}() {{ self.setLed({i}); }}" for i in range(4))
    leds = " ".join(f"self.setLed({i}); self.sleep();" for i in range(12))
    text = (f"role A {{ self.x() > 0; {commands} command big() {{ {leds} }} }}\ndeployment {{ A }}")
    result = check_text(text)
    assert {d.code for d in result.diagnostics} & {"W601", "E601"}


def run(program, loss: float, seconds: float, seed: int = 5) -> LatticeWorld:
    world = LatticeWorld(load_config("car7"), role_table(program), seed=seed, packet_loss=loss)
    for name in program.injection:  # back to back, as rdcd simulate does
        world.inject(program.fragment(name).code)
    world.advance(seconds)
    return world


@pytest.mark.parametrize("loss", [0.0, 0.1])
def test_the_chain_of_a_command_runs_every_statement_in_order(loss):
    _, program = compiled(WHEELS.format(member=SHOW, call="show(3)"))
    world = run(program, loss, 40.0)
    told = next(s.index for s in program.states if s.name == "told")
    wheels = [m for m, role in world.roles_by_name().items() if role and role.endswith("Wheel")]
    assert len(wheels) == 4
    for m in wheels:
        assert world.runtimes[m].state[told] == 3  # the last statement ran, with the argument
        assert world.runtimes[m].led == 0
        assert round(world.hals[m].joint_angle_deg()) == 90
        assert not world.runtimes[m].errors


def test_the_chain_of_a_behaviour_repeats():
    _, program = compiled(WHEELS.format(member=GAIT, call="noop()"))
    world = run(program, 0.1, 30.0)
    told = next(s.index for s in program.states if s.name == "told")
    wheels = [m for m, role in world.roles_by_name().items() if role and role.endswith("Wheel")]
    assert wheels and all(world.runtimes[m].state[told] >= 4 for m in wheels)
    assert all(not world.runtimes[m].errors for m in wheels)
