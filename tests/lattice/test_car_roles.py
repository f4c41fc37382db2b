"""The shipped cars under a hand-assembled version of the obstacle program's role discovery and
detection (examples/obstacle_avoidance.rdcd): every module gets its ``role_expected`` and the
watched sensor of each front wheel, and only those, sees a wall ahead."""

from __future__ import annotations

import pytest

from sim.config import load_config
from vm.isa.assembler import assemble
from vm.lattice.world import LatticeWorld
from vm.roles import RoleTable

ROLES = RoleTable({1: "RightWheel", 2: "LeftWheel", 3: "Wheel", 4: "Axle"},
                  {1: frozenset({3}), 2: frozenset({3})})

WHEELS = assemble("""
    CENTER_POSITION_EW
    IF_FALSE_GOTO done
    CONNECTED_SIZEOF
    EQUALS_1
    IF_FALSE_GOTO done
    CONNECTED_DIR_SIZEOF UP
    EQUALS_1
    IF_FALSE_GOTO done
    CONNECTED_DIR_SIZEOF EAST
    EQUALS_1
    IF_FALSE_GOTO left
    SET_ROLE_NOTIFY 1
    GOTO done
left:
    CONNECTED_DIR_SIZEOF WEST
    EQUALS_1
    IF_FALSE_GOTO done
    SET_ROLE_NOTIFY 2
done:
    MIGRATE_CONTINUE
""")

AXLES = assemble("""
    CONNECTED_ROLE DOWN 3
    SIZEOF
    PUSH 0
    GREATER
    IF_FALSE_GOTO done
    SET_ROLE_NOTIFY 4
done:
    MIGRATE_CONTINUE
""")

FRONT_SENSORS = assemble("""
    PUSH 0
    COORD_Y_GREATER
    IF_FALSE_GOTO done
    HAS_ROLE 1
    IF_FALSE_GOTO left
    HANDLE_EVENT EVENT_PROXIMITY_5 handler end-handler
    GOTO done
left:
    HAS_ROLE 2
    IF_FALSE_GOTO done
    HANDLE_EVENT EVENT_PROXIMITY_1 handler end-handler
done:
    MIGRATE_CONTINUE
handler:
    SET_LED 1
    END_TERMINATE
end:
""")


@pytest.mark.parametrize("name", ["car7", "car11", "car8-cyclic", "car17-wide"])
@pytest.mark.parametrize("loss", [0.0, 0.1])
def test_roles_and_front_sensors(name: str, loss: float) -> None:
    structure = load_config(name)
    world = LatticeWorld(structure, ROLES, seed=11, packet_loss=loss)
    for fragment in (WHEELS, AXLES, FRONT_SENSORS):
        world.inject(fragment)
        assert world.run_until_quiet(30.0)
    assert world.roles_by_name() == structure.expected_roles
    world.advance(1.0)
    assert not any(hal.led for hal in world.hals.values())
    # a wall two lattice steps ahead of the front wheels
    xs = [m.position[0] for m in structure.modules.values()]
    wall = {(x, 3, z) for x in range(min(xs) - 2, max(xs) + 3) for z in range(-4, 2)}
    world.set_obstacles(frozenset(wall))
    world.advance(0.5)
    fired = sorted(m for m, hal in world.hals.items() if hal.led)
    front_wheels = sorted(m for m, spec in structure.modules.items()
                          if spec.position[1] > 0 and "Wheel" in str(structure.expected_roles[m]))
    assert fired == front_wheels and len(front_wheels) in (2, 4)
    assert all(not s.errors for s in world.states())
