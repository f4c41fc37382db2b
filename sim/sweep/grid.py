"""The grid of an experiment: axes of option values, enumerated lazily by index.

A grid of 10^9 cells is never materialised: an axis is either a list (written out in the
experiment file, so already in memory) or an arithmetic range, and run ``i`` is found by
mixed-radix decomposition of ``i``. The last axis varies fastest.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Axis:
    name: str
    values: tuple[Any, ...] | None = None  # a list axis
    start: float = 0  # a range axis: start + i * step for i < count
    step: float = 1
    count: int = 0
    integer: bool = False

    def __len__(self) -> int:
        return len(self.values) if self.values is not None else self.count

    def __getitem__(self, index: int) -> Any:
        if self.values is not None:
            return self.values[index]
        if self.integer:
            return int(self.start) + index * int(self.step)
        return round(self.start + index * self.step, 12)  # 0.1 * 3 reads as 0.3, not 0.30000000000000004

    def ends(self) -> list[Any]:
        """The values to validate for a range: its first and last (all values lie between)."""
        if self.values is not None:
            return list(self.values)
        return [self[0], self[len(self) - 1]] if len(self) else []


def range_axis(name: str, start: float, stop: float, step: float, integer: bool) -> Axis:
    """Values start, start + step, ... up to stop inclusive (a tiny tolerance for float steps)."""
    count = math.floor((stop - start) / step + 1e-9) + 1 if (stop - start) * step >= 0 else 0
    return Axis(name, None, start, step, max(count, 0), integer)


@dataclass(frozen=True)
class Grid:
    axes: tuple[Axis, ...]

    @property
    def size(self) -> int:
        return math.prod(len(a) for a in self.axes)

    @property
    def names(self) -> list[str]:
        return [a.name for a in self.axes]

    def point(self, index: int) -> dict[str, Any]:
        """The option values of run ``index`` (0 <= index < size)."""
        values: dict[str, Any] = {}
        for axis in reversed(self.axes):
            index, digit = divmod(index, len(axis))
            values[axis.name] = axis[digit]
        return {a.name: values[a.name] for a in self.axes}

    def points(self, limit: int | None = None) -> Iterator[dict[str, Any]]:
        for index in range(self.size if limit is None else min(limit, self.size)):
            yield self.point(index)
