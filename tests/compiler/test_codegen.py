"""Code generation phases on small programs: discovery, folding, statements, entry code."""

from __future__ import annotations

import pytest

from rdcd_core.compiler.render import base_of, instruction_text, regions
from vm.isa.disassembler import disassemble


def text(program, name=None):
    fragment = program.fragments[0] if name is None else program.fragment(name)
    roles = {r.id: r.name for r in program.roles}
    found = regions(fragment.code)
    return [instruction_text(d, roles, base_of(found, d.offset)) for d in disassemble(fragment.code)]


def ops(program, name=None):
    return [line.split()[0] for line in text(program, name)]


def test_single_role_discovery(compile_text):
    program = compile_text("role A { self.center_position == UP_DOWN; }\ndeployment { A }")
    assert text(program) == ["CENTER_POSITION_UD", "IF_FALSE_GOTO L5", "SET_ROLE_NOTIFY A",
                             "MIGRATE_CONTINUE"]


def test_tests_implied_by_earlier_ones_are_simplified(compile_text):
    program = compile_text("role A { sizeof(self.total_connected()) == 1; sizeof(self.connected(UP)) == 1;"
                           " sizeof(self.total_connected()) <= 8; }\ndeployment { A }")
    assert ops(program) == ["CONNECTED_SIZEOF", "EQUALS_1", "IF_FALSE_GOTO", "CONNECTED_DIR_SIZEOF",
                            "IF_FALSE_GOTO", "SET_ROLE_NOTIFY", "MIGRATE_CONTINUE"]


def test_siblings_share_one_discovery_fragment(obstacle):
    discovery = [f for f in obstacle.fragments if f.kind == "discovery"]
    assert [f.name for f in discovery] == ["discover_RightWheel_LeftWheel", "discover_Axle"]
    lines = text(obstacle, "discover_RightWheel_LeftWheel")
    assert lines.count("CENTER_POSITION_EW") == 1
    assert "CONNECTED_DIR_SIZEOF WEST" not in lines  # implied once EAST failed
    assert {"SET_ROLE_NOTIFY RightWheel", "SET_ROLE_NOTIFY LeftWheel"} <= set(lines)


def test_dependent_discovery_waits_then_tests_neighbours(obstacle):
    lines = text(obstacle, "discover_Axle")
    assert lines[:2] == ["SLEEP", "CONNECTED_DOWN_ROLE Wheel"]


def test_equality_uses_original_instructions_only(compile_text):
    program = compile_text("role A { self.y() == 5; self.x() != -2; }\ndeployment { A }")
    names = ops(program)
    assert "EQUALS" not in names and "SUB" not in names
    assert {"COORD_Y_GREATER", "COORD_Y_LESSER", "COORD_X_GREATER", "COORD_X_LESSER"} <= set(names)


def test_constants_are_folded_per_concrete_role(obstacle):
    right = "\n".join(text(obstacle, "discover_RightWheel_LeftWheel"))
    left = "\n".join(text(obstacle, "LeftWheel_entry"))
    assert "ENABLE_EVENT EVENT_PROXIMITY_5" in right and "EVAL_COMMAND ROTATE_CCW 1" in right
    assert "ENABLE_EVENT EVENT_PROXIMITY_1" in left and "EVAL_COMMAND ROTATE_CW 1" in left


def test_assume_role_switches_and_restores(obstacle):
    lines = text(obstacle, "discover_RightWheel_LeftWheel")
    start = lines.index("SET_ROLE_NOTIFY Reverse@RightWheel")
    assert lines[start + 1:] == ["EVAL_COMMAND ROTATE_CCW 1", "SLEEP_ROTATIONS 3",
                                 "EVAL_COMMAND ROTATE_CW 1", "ENABLE_EVENT EVENT_PROXIMITY_5",
                                 "SET_ROLE_NOTIFY RightWheel", "END_TERMINATE"]


def test_plain_methods_are_inlined(compile_text):
    program = compile_text("role A { self.y() > 0; startup s() { self.blink(); self.blink(); }\n"
                           "  blink() { self.setLed(1); self.sleep(); } }\ndeployment { A }")
    lines = text(program)
    assert lines.count("SET_LED 1") == 2 and lines.count("SLEEP") == 2


def test_behaviour_is_installed_started_and_repeats(obstacle):
    lines = text(obstacle, "discover_Axle")
    install = next(line for line in lines if line.startswith("INSTALL_COMMAND Axle"))
    assert install.split()[2] == "USER_0"
    assert "EVAL_COMMAND USER_0 0" in lines
    assert lines.count("END_REPEAT") >= 1
    assert "EVAL_COMMAND ROTATE_TO 3" in lines and "EVAL_COMMAND ROTATE_TO -3" in lines


def test_behaviour_checks_the_role_when_a_later_role_may_replace_it(compile_text):
    program = compile_text("role A { self.y() > 0; behavior b() { self.sleep(); } }\n"
                           "role B { self.x() > 0; }\ndeployment { A, B }")
    lines = text(program, "discover_A")
    body = lines[lines.index("MIGRATE_CONTINUE") + 1:]
    assert body == ["HAS_ROLE A", "IF_FALSE_GOTO L20", "SLEEP", "END_REPEAT"]


def test_global_command_targets_the_named_role(compile_text):
    program = compile_text(
        "abstract role S { sizeof(self.total_connected()) >= 1; command flash() { self.setLed(7); } }\n"
        "role H extends S { self.y() > 0; startup s() { S.flash(); } }\ndeployment { H }")
    assert "SEND_COMMAND S USER_0 0" in text(program)
    assert {r.name for r in program.roles} == {"H", "S"}


def test_handler_body_is_embedded(compile_text):
    program = compile_text("role A { self.y() > 0;\n startup s() { self.handleEvent(EVENT_PROXIMITY_3,"
                           " { self.setLed(2); }); } }\ndeployment { A }")
    lines = text(program)
    assert any(line.startswith("HANDLE_EVENT EVENT_PROXIMITY_3") for line in lines)
    assert lines[-2:] == ["SET_LED 2", "END_TERMINATE"]


def test_mixin_commands_override_while_the_mixin_is_played(compile_text):
    program = compile_text(
        "abstract role W { self.center_position == EAST_WEST; command go() { self.setLed(1); }\n"
        "  command hop() { self.assumeRole(M, { W.go(); }); } }\n"
        "role A extends W { self.y() > 0; }\n"
        "role M modifies W { command go() { self.setLed(2); } }\ndeployment { A }")
    lines = [line for fragment in program.fragments for line in text(program, fragment.name)]
    assert "INSTALL_COMMAND A USER_0 @" in " ".join(lines)
    installs = [line for line in lines if line.startswith("INSTALL_COMMAND")]
    assert installs[-1].startswith("INSTALL_COMMAND M@A USER_0")
    assert "SET_LED 2" in lines and "SET_LED 1" in lines


def test_constants_move_across_comparisons_to_avoid_extensions(compile_text):
    program = compile_text("role A { self.x() + 1 > 0; 3 - self.y() < 2; self.z() - 2 == 1; }\n"
                           "deployment { A }")
    assert program.diagnostics == []
    names = ops(program)
    assert not {"ADD", "SUB", "EQUALS"} & set(names)
    assert "COORD_X_LESSER" in names and "COORD_Y_GREATER" in names
    # the original firmware has no instruction that reads z; x and y still compile (--strict-isa)
    program = compile_text("role A { self.x() + 1 > 0; 3 - self.y() < 2; self.y() - 2 == 1; }\n"
                           "deployment { A }", strict_isa=True)
    assert program.diagnostics == [] and program.target == "original"
    assert not {"ADD", "SUB", "EQUALS", "LESSER", "COORD_Y"} & set(ops(program))


class Recorder:
    """A module for the interpreter: fixed coordinates, records the commands it runs."""

    def __init__(self, y: int) -> None:
        self.y, self.commands = y, []

    def coords(self):
        return (0, self.y, 0)

    def eval_command(self, command, arg):
        self.commands.append((command, arg))

    def __getattr__(self, name):
        return lambda *args: 0


def test_speed_known_only_at_run_time_uses_turn_stack(compile_text):
    """The default target pops the speed (TURN_STACK, issue 25); the firmware branches and APPLYs."""
    from vm.interpreter import Frame, run

    program = compile_text("role A { startup s() { self.turnContinuously(self.y()); } }\ndeployment { A }")
    assert program.diagnostics == [] and "TURN_STACK" in ops(program) and "APPLY" not in ops(program)
    firmware = compile_text("role A { startup s() {\n"
                            "  self.turnContinuously(sizeof(self.total_connected())); } }\n"
                            "deployment { A }", target="original")
    assert not firmware.has_errors and "APPLY" in ops(firmware) and "TURN_STACK" not in ops(firmware)
    for y, expected in ((3, (1, 3)), (-2, (2, 2)), (0, (3, 0))):
        module = Recorder(y)
        run(Frame(program.fragments[0].code), module)
        assert module.commands == [expected]


STATE_EQUALS = """state s := 0;
state hit := 0;
role A {{
  self.center_position == NORTH_SOUTH;
  startup set() {{ s := {value}; }}
  behavior look() {{ if (s {op} 12) hit := 1; else hit := 2; }}
}}
deployment {{ A }}"""


def test_a_state_against_a_constant_is_one_equals(compile_text):
    # LOAD_STATE, PUSH 12, EQUALS: four bytes fewer than reading the state twice for > and <
    names = ops(compile_text(STATE_EQUALS.format(value=1, op="==")))
    assert "EQUALS" in names and "GREATER" not in names and "LESSER" not in names
    # a constant of 0..4 keeps its one-byte test (EQUALS_k)
    names = ops(compile_text(STATE_EQUALS.format(value=1, op="==").replace("s == 12", "s == 3")))
    assert "EQUALS_3" in names and "EQUALS" not in names


@pytest.mark.parametrize("op", ["==", "!="])
@pytest.mark.parametrize("value", [-128, -12, 0, 11, 12, 13, 127])
def test_a_state_against_a_constant_means_what_it_says_on_the_vm(op, value):
    from rdcd_core.compiler import compile_model
    from rdcd_core.frontend import check_text
    from sim.config import load_config
    from sim.run import Options, simulate

    text = STATE_EQUALS.format(value=value, op=op)
    result = check_text(text)
    assert not result.has_errors
    report = simulate(compile_model(result.model, text=text), load_config("snake1"),
                      Options(world="lattice", config="snake1", obstacle="none", duration=3))
    [module] = report["modules"]
    assert module["final_state"]["hit"] == (1 if (value == 12) == (op == "==") else 2)
