"""The ATRON firmware's data and tables, shared by ``vm.runtime_firmware`` (its controller) and
``vm.firmware_interpreter`` (its interpreter): limits, error numbers, the context a stored program
carries, the tasks of its queue, and navigation.c's channel and coordinate tables."""

from __future__ import annotations

from collections.abc import Generator
from dataclasses import dataclass

from vm import navigation as nav

STEP = -1.0  # yielded: resume at the next scheduler step
SLOTS = 10  # MAX_N_STORED_PROGRAMS
QUEUE = 10  # MAX_N_ENQUEUED_TASKS: a ring of 10, so 9 tasks at most
MAX_STACK = 5
MAX_INSTRUCTIONS = 100  # a run ends in error on the 102nd instruction
MAX_ROLES = 15
ROLE_COMMANDS = 5
NONE = 255  # no vector, no command
DISABLED = 128
LOAD_DELAY_S = 8.0  # dcd_action: before each fragment
SLEEP_S = 1.0
TASK_INTERPRET, TASK_COMMAND = 1, 2
NS, EW, UD = nav.NORTH_SOUTH, nav.EAST_WEST, nav.UP_DOWN
NORTH, EAST, WEST, UP, DOWN = 6, 4, 5, 8, 9

# dcdError.h: the firmware's error numbers
ERRORS = {1: "program store full", 2: "task queue full", 3: "unknown message", 5: "illegal receiver rotation",
          6: "illegal virtual channel", 7: "stack overflow", 9: "unknown instruction",
          11: "instruction count exceeded", 12: "illegal connection direction", 13: "illegal axis direction",
          18: "illegal command install", 19: "illegal function", 21: "illegal argument index"}

Wait = Generator[float, None, int]


class Halt(Exception):
    """report_error: the firmware stops the module (it never returns)."""


@dataclass
class Context:
    x: int = 0
    y: int = 0
    z: int = 0
    r: int = NS
    in_vch: int = 0
    in_pch: int = 0
    program_id: int = 0


@dataclass
class Stored:
    context: Context
    code: bytes = b""


@dataclass
class FwTask:
    kind: int
    discard: bool = False
    slot: int = 0  # TASK_INTERPRET
    arg: int = 0
    role: int = 0  # TASK_COMMAND: the packet's fields
    command: int = 0
    argument: int = 0
    pch: int = 0
    x: int = 0
    y: int = 0
    z: int = 0
    r: int = 0
    vch: int = 0
    packet_id: int = 0


def s8(v: int) -> int:
    v &= 0xFF
    return v - 256 if v > 127 else v


# navigation.c: compute_receiver_coordinates, per axis and virtual channel: (dx, dy, dz, axis, receiver vch)
RECEIVER = {
    NS: [(0, 1, 1, UD, 6), (-1, 1, 0, EW, 3), (0, 1, -1, UD, 2), (1, 1, 0, EW, 7),
         (0, -1, 1, UD, 4), (-1, -1, 0, EW, 1), (0, -1, -1, UD, 0), (1, -1, 0, EW, 5)],
    EW: [(1, 0, 1, UD, 7), (1, 1, 0, NS, 5), (1, 0, -1, UD, 3), (1, -1, 0, NS, 1),
         (-1, 0, 1, UD, 5), (-1, 1, 0, NS, 7), (-1, 0, -1, UD, 1), (-1, -1, 0, NS, 3)],
    UD: [(0, 1, 1, NS, 6), (1, 0, 1, EW, 6), (0, -1, 1, NS, 2), (-1, 0, 1, EW, 2),
         (0, 1, -1, NS, 4), (-1, 0, -1, EW, 4), (0, -1, -1, NS, 0), (1, 0, -1, EW, 0)],
}


def virtual_to_physical(ctx: Context, vch: int) -> int:
    """navigation.c's virtual2physical: the physical channel of ``vch`` given how ``ctx`` arrived."""
    sides = [[0, 1, 2, 3], [4, 5, 6, 7]]
    vc, pc = ctx.in_vch, ctx.in_pch
    change = (vc < 4 and pc > 3) or (vc > 3 and pc < 4)
    if change:
        (sides[0][0], sides[1][0]) = (sides[1][0], sides[0][0])
        (sides[0][1], sides[1][3]) = (sides[1][3], sides[0][1])
        (sides[0][2], sides[1][2]) = (sides[1][2], sides[0][2])
        (sides[0][3], sides[1][1]) = (sides[1][1], sides[0][3])
    side, local = (1, vc - 4) if vc > 3 else (0, vc)
    for _ in range(8):
        if sides[side][local] == pc:
            break
        for s in sides:
            if change:
                s[:] = s[1:] + s[:1]
            else:
                s[:] = s[3:] + s[:3]
    return sides[1][vch - 4] if vch > 3 else sides[0][vch]


def joint_quarter(angle_deg: float) -> int:
    """The ATRON API's getJointPosition: which quarter of a turn the joint is nearest."""
    enc = (angle_deg % 360.0) / 360.0
    if enc <= 0.125 or abs(enc - 1.0) < 0.125:
        return 0
    for quarter in (1, 2, 3):
        if abs(enc - quarter / 4) <= 0.125:
            return quarter
    return 0
