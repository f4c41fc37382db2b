"""A bounded space of abstract module states, for deciding invariants (docs/language.md).

A state is an axis, a set of attached connectors (virtual channels 0..7) and representative
coordinates; the neighbour roles are a parameter of the evaluation. A set of states is a Python
int used as a bitset, so one invariant is evaluated over every state at once: an expression's
value is a map ``value -> set of states where it has that value``.
"""

from __future__ import annotations

from rdcd_core.types import PREDEFINED_VALUES

AXES = (PREDEFINED_VALUES["EAST_WEST"].code, PREDEFINED_VALUES["NORTH_SOUTH"].code,
        PREDEFINED_VALUES["UP_DOWN"].code)
AXIS_NAMES = {value.code: name for name, value in PREDEFINED_VALUES.items() if name in
              ("EAST_WEST", "NORTH_SOUTH", "UP_DOWN")}

# Offsets of the virtual channels 0..7 per axis (docs/vm.md).
_OFFSETS = {
    "NORTH_SOUTH": ((0, 1, 1), (-1, 1, 0), (0, 1, -1), (1, 1, 0),
                    (0, -1, 1), (-1, -1, 0), (0, -1, -1), (1, -1, 0)),
    "EAST_WEST": ((1, 0, 1), (1, 1, 0), (1, 0, -1), (1, -1, 0),
                  (-1, 0, 1), (-1, 1, 0), (-1, 0, -1), (-1, -1, 0)),
    "UP_DOWN": ((0, 1, 1), (1, 0, 1), (0, -1, 1), (-1, 0, 1),
                (0, 1, -1), (1, 0, -1), (0, -1, -1), (-1, 0, -1)),
}
_DIRECTIONS = {"EAST": (0, 1), "WEST": (0, -1), "NORTH": (1, 1), "SOUTH": (1, -1),
               "UP": (2, 1), "DOWN": (2, -1)}


def _facing() -> dict[tuple[int, int], int]:
    table: dict[tuple[int, int], int] = {}
    for axis_name, offsets in _OFFSETS.items():
        axis = PREDEFINED_VALUES[axis_name].code
        for dir_name, (component, sign) in _DIRECTIONS.items():
            bits = 0
            for channel, offset in enumerate(offsets):
                if offset[component] * sign > 0:
                    bits |= 1 << channel
            table[(axis, PREDEFINED_VALUES[dir_name].code)] = bits
    return table


FACING = _facing()  # (axis code, dir code) -> connset of the channels facing that direction

Values = dict[int, int]  # value -> states
_ODD = {"NORTH_SOUTH": set(), "EAST_WEST": {"x", "y"}, "UP_DOWN": {"y", "z"}}


class StateSpace:
    def __init__(self, coordinates: dict[str, list[int]]) -> None:
        self.reps = {c: coordinates.get(c) or [0] for c in "xyz"}
        nx, ny, nz = (len(self.reps[c]) for c in "xyz")
        self.block = nx * ny * nz  # coordinate states per (axis, connset)
        self.blocks = len(AXES) * 256
        self._block_full = (1 << self.block) - 1
        self._cache: dict[object, Values] = {}
        self.full = self._lattice_states(set(coordinates))

    def _lattice_states(self, used: set[str]) -> int:
        """Every state whose coordinates fit the axis on the lattice (docs/vm.md: NS modules
        sit where x, y, z are even, EW where x and y are odd, UD where y and z are odd)."""
        full = 0
        repeat = sum(1 << (k * self.block) for k in range(256))
        for index, axis in enumerate(AXES):
            odd = _ODD[AXIS_NAMES[axis]]
            pattern = 0
            for bit in range(self.block):
                coords = self._coords(bit)
                if all(coords[c] % 2 == (c in odd) for c in used):
                    pattern |= 1 << bit
            full |= (pattern * repeat) << (index * 256 * self.block)
        return full

    def _coords(self, bit: int) -> dict[str, int]:
        ny, nz = len(self.reps["y"]), len(self.reps["z"])
        xi, rest = divmod(bit, ny * nz)
        yi, zi = divmod(rest, nz)
        return {"x": self.reps["x"][xi], "y": self.reps["y"][yi], "z": self.reps["z"][zi]}

    def _at(self, axis_index: int, connset: int) -> int:
        return self._block_full << ((axis_index * 256 + connset) * self.block)

    def axis(self) -> Values:
        return self._cached("axis", lambda: {
            code: ((1 << (256 * self.block)) - 1) << (index * 256 * self.block)
            for index, code in enumerate(AXES)})

    def total_connected(self) -> Values:
        def build() -> Values:
            out: Values = {}
            for connset in range(256):
                out[connset] = sum(self._at(a, connset) for a in range(len(AXES)))
            return out
        return self._cached("total", build)

    def connected(self, direction: int) -> Values:
        def build() -> Values:
            out: Values = {}
            for index, axis in enumerate(AXES):
                facing = FACING.get((axis, direction), 0)
                for connset in range(256):
                    value = connset & facing
                    out[value] = out.get(value, 0) | self._at(index, connset)
            return out
        return self._cached(("connected", direction), build)

    def coordinate(self, name: str) -> Values:
        def build() -> Values:
            nx, ny, nz = (len(self.reps[c]) for c in "xyz")
            repeat = sum(1 << (k * self.block) for k in range(self.blocks))
            out: Values = {}
            for bit in range(self.block):
                xi, rest = divmod(bit, ny * nz)
                yi, zi = divmod(rest, nz)
                index = {"x": xi, "y": yi, "z": zi}[name]
                value = self.reps[name][index]
                out[value] = out.get(value, 0) | (1 << bit)
            return {value: pattern * repeat for value, pattern in out.items()}
        return self._cached(("coordinate", name), build)

    def is_cached(self, values: Values) -> bool:
        return any(values is table for table in self._cache.values())

    def _cached(self, key: object, build) -> Values:  # type: ignore[no-untyped-def]
        found = self._cache.get(key)
        if found is None:
            found = build()
            self._cache[key] = found
        return found

    def describe(self, states: int) -> tuple[str, int, dict[str, int]]:
        """Axis name, connset and coordinates of the first state in ``states``."""
        index = (states & -states).bit_length() - 1
        block, within = divmod(index, self.block)
        axis_index, connset = divmod(block, 256)
        return AXIS_NAMES[AXES[axis_index]], connset, self._coords(within)
