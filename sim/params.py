"""Every physical parameter of the simulated ATRON world, in one place (docs/simulator.md).

SI units throughout. Change a value here, not in the code that uses it.
"""

from __future__ import annotations

import math

# --- the module --------------------------------------------------------------------------
MODULE_RADIUS = 0.055  # m, diameter 0.110
MODULE_MASS = 0.850  # kg, split equally between the two hemispheres
HEMISPHERE_MASS = MODULE_MASS / 2
# Centre of mass of a solid hemisphere lies 3R/8 from the joint plane.
HEMISPHERE_COM_OFFSET = 3 * MODULE_RADIUS / 8
LATTICE_UNIT = 0.08  # m per lattice unit; neighbours are (±1, ±1, 0) units apart = 0.113 m

# --- the joint ---------------------------------------------------------------------------
JOINT_TURN_PERIOD_S = 6.0  # one full turn in 6 s at speed 1
JOINT_SPEED = 2 * math.pi / JOINT_TURN_PERIOD_S  # rad/s at speed 1
# N·m: one module lifts two others. USSR's "realistic" ATRON drives its joint with the same
# figure (alt-ussr JMEATRONFactory.addCenterActuator: setControlParameters(3f, 2π/6 rad/s),
# "just able to lift two"); docs/simulator.md.
JOINT_MAX_TORQUE = 3.0
JOINT_POSITION_GAIN = 4.0  # 1/s: proportional gain of rotate-to, capped at the joint speed
JOINT_ANGLE_TOLERANCE_DEG = 1.5  # a rotate-to is done within this angle
JOINT_DAMPING = 0.0
# A rotate-to whose error has not shrunk by JOINT_STALL_DEG for JOINT_STALL_S has failed (the load
# is more than the torque lifts): the joint gives up and holds, and the failure is an event.
JOINT_STALL_DEG = 2.0
JOINT_STALL_S = 1.0

# --- changing shape (docs/simulator.md "Structures that change") -----------------------------
# A male connector latches onto a female one of another module only when their connector points
# are closer than this: USSR's ATRON (alt-ussr src/ussr/samples/atron/ATRON.java,
# common.setMaxConnectionDistance(0.03f)). Connector points sit on the shell, under the connector.
LATCH_DISTANCE = 0.03  # m
# After a quarter turn, a module's centre is on its lattice cell if it is within this distance of
# it, in the frame of the entry module (the structure's frame); else the turn has failed.
SNAP_DISTANCE = 0.02  # m

# --- wheels: rubber ring around the free hemisphere ---------------------------------------
RING_RADIUS = 0.059  # m: a few mm proud of the 0.055 m shell, so only the ring touches the ground
RING_AXIAL_OFFSET = 0.006  # m from the joint plane into the free hemisphere
RING_WIDTH = 0.012  # m, along the axis
RING_FRICTION = 0.7  # Coulomb friction (times GROUND_FRICTION); higher lets wheel scrub overpower 3 N·m axles
RING_AXIAL_FRICTION_SCALE = 1.0  # friction along the wheel axis (sideways slip), relative
RING_ROLLING_FRICTION = 0.0002
RING_SPINNING_FRICTION = 0.005  # m: resists the contact patch twisting as steered bogies turn
SHELL_FRICTION = 0.4  # hard plastic shell
GROUND_FRICTION = 1.0
RESTITUTION = 0.0
SPAWN_CLEARANCE = 0.001  # m above the ground at start
# The multibody's base: a tiny anchor fixed to the entry module's rigid group (sim/robot.py).
ANCHOR_MASS = 0.001  # kg
ANCHOR_INERTIA = 1e-6  # kg·m², each principal moment

# --- infrared sensors and links -----------------------------------------------------------
IR_RANGE = 0.15  # m from the module surface
IR_SENSOR_OFFSET = 0.002  # m: a sensor's rays start this far out from the shell, under its connector
IR_CONE_HALF_ANGLE_DEG = 20.0
IR_RAYS = 7  # one central ray plus a ring of IR_RAYS - 1 at the cone edge
IR_RATE_HZ = 20.0  # proximity sampling rate
IR_SEES_GROUND = False  # the floor is not reported as an obstacle
IR_LATENCY_S = 0.010  # per packet

# --- simulation ----------------------------------------------------------------------------
PHYSICS_HZ = 240.0
SOLVER_ITERATIONS = 20  # fewer (10-15) is faster but lets steered wheels slip into collisions
VM_HZ = 20.0  # module runtime steps (scheduler ticks) per simulated second
TRAJECTORY_HZ = 20.0
GRAVITY = -9.81
COLLISION_MARGIN = 0.002  # m: closer than this to an obstacle counts as a collision

# --- worlds --------------------------------------------------------------------------------
WALL_THICKNESS = 0.05
WALL_WIDTH = 3.0
WALL_HEIGHT = 0.3
BOX_HEIGHT = 0.3
