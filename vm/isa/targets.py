"""The targets a program can be compiled for and a VM profile can behave like (docs/architecture.md,
"Targets").

Each target is one description: which opcodes it executes, its limits and its quirks. The compiler,
the verifier and the VM profile read these; no ``if original:`` elsewhere. ``default`` is this
project's corrected DCD-VM (docs/vm.md); ``original`` is the ATRON firmware of 2007 as
docs/vm.md describes it.
"""

from __future__ import annotations

from dataclasses import dataclass

from vm.isa.opcodes import BY_NAME, INSTRUCTIONS, MAX_STACK, MAX_STEPS_PER_RUN, PROGRAM_SLOTS, SLOT_BYTES


@dataclass(frozen=True, slots=True)
class Quirks:
    """The firmware's bugs (docs/vm.md) that a VM profile reproduces and the compiler avoids."""

    enable_event_toggles: bool = False  # ENABLE_EVENT flips the disabled flag instead of clearing it
    connected_dir_sizeof_popcount_of_count: bool = False  # CONNECTED_DIR_SIZEOF: bits set in the count
    connected_dir_sizeof_limited: bool = False  # only NS {NORTH, DOWN} and EW {UP, EAST, WEST, DOWN, NORTH}
    connected_physical_bits: bool = False  # CONNECTED: bit p+1 for physical channel p, channel 7 lost
    handler_refires_with_zero: bool = False  # a handler runs with argument 0, again every step it sees
    apply_64_broadcasts: bool = False  # APPLY with f = 64 broadcasts command a to every role
    no_duplicate_suppression: bool = False  # programs circulate in cyclic structures
    ud_offsets_swapped: bool = False  # UD channel 5/7 x-offsets swapped (coordinates learned wrong)
    unknown_instruction_halts: bool = False  # an opcode it does not execute halts the module
    no_acknowledgements: bool = False  # packets are sent once: no acks, no retransmission (docs/vm.md)
    negate_wraps: bool = False  # NEGATE of -128 gives -128 (8-bit wrap) instead of 127 (saturation)
    # the module runs the firmware's own controller (vm.runtime_firmware, docs/firmware.md): one
    # scheduler step checks the sensors then runs one task; SLEEP, handlers and commands block the
    # module; contexts per stored program; the entry module loads the fragments 8 s apart first
    firmware_controller: bool = False


@dataclass(frozen=True, slots=True)
class Target:
    name: str
    opcodes: frozenset[int]  # opcodes it executes (bytes >= 128 are always small constants)
    max_stack: int
    max_steps_per_run: int
    slot_bytes: int
    program_slots: int
    quirks: Quirks
    description: str
    # (axis, direction) pairs for which CONNECTED_DIR_SIZEOF runs; None = every pair. Elsewhere the
    # firmware halts the module (docs/vm.md).
    dir_sizeof_pairs: frozenset[tuple[int, int]] | None = None
    # The program is built into the firmware as a C file (dcd_action, check_role_instanceof) rather
    # than read at run time: the compiler's C form is that file (docs/vm.md, "Loading").
    loads_c_file: bool = False

    def implements(self, opcode: int) -> bool:
        return opcode >= 128 or opcode in self.opcodes

    def implements_name(self, name: str) -> bool:
        """Whether the instruction called ``name`` (``vm.isa.opcodes``) runs on this target."""
        info = BY_NAME.get(name)
        return info is not None and info.opcode in self.opcodes

    def dir_sizeof_runs(self, axis: int, direction: int) -> bool:
        return self.dir_sizeof_pairs is None or (axis, direction) in self.dir_sizeof_pairs


def _ranges(*spans: tuple[int, int]) -> frozenset[int]:
    return frozenset(op for low, high in spans for op in range(low, high + 1))


DEFAULT = Target(
    name="default",
    opcodes=frozenset(ins.opcode for ins in INSTRUCTIONS),
    max_stack=MAX_STACK,
    max_steps_per_run=MAX_STEPS_PER_RUN,
    slot_bytes=SLOT_BYTES,
    program_slots=PROGRAM_SLOTS,
    quirks=Quirks(),
    description="this project's DCD-VM: the instruction set of docs/vm.md with its extensions",
)

ORIGINAL = Target(
    name="original",
    # docs/vm.md: 1–7, 12–18, 22, 24–27, 30–34, 36, 42–49, 51–55, 127
    opcodes=_ranges((1, 7), (12, 18), (22, 22), (24, 27), (30, 34), (36, 36), (42, 49), (51, 55),
                    (127, 127)),
    max_stack=5,
    max_steps_per_run=100,
    slot_bytes=SLOT_BYTES,
    program_slots=PROGRAM_SLOTS,
    quirks=Quirks(enable_event_toggles=True, connected_dir_sizeof_popcount_of_count=True,
                  connected_dir_sizeof_limited=True, connected_physical_bits=True,
                  handler_refires_with_zero=True, apply_64_broadcasts=True,
                  no_duplicate_suppression=True, ud_offsets_swapped=True,
                  unknown_instruction_halts=True, no_acknowledgements=True, negate_wraps=True,
                  firmware_controller=True),
    description="the ATRON firmware of 2007 (docs/firmware.md): fewer opcodes, stack 5, 100 steps, quirks",
    # axis codes EW 1, NS 2; directions EAST 4, WEST 5, NORTH 6, UP 8, DOWN 9 (docs/vm.md)
    dir_sizeof_pairs=frozenset({(2, 6), (2, 9), (1, 8), (1, 4), (1, 5), (1, 9), (1, 6)}),
    loads_c_file=True,
)

TARGETS: dict[str, Target] = {target.name: target for target in (DEFAULT, ORIGINAL)}
