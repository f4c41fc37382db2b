"""The types of RDCD (docs/language.md) and its predefined values (§5.3, encodings docs/vm.md)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class Type(StrEnum):
    INT = "int"
    BOOL = "bool"
    CONNSET = "connset"
    AXIS = "axis"
    DIR = "dir"
    EVENT = "event"
    ROLE = "role"
    BLOCK = "block"
    VALUES = "values"  # the values of a module state that the neighbours published
    VOID = "void"


@dataclass(frozen=True, slots=True)
class PredefinedValue:
    name: str
    type: Type
    code: int  # the byte the DCD-VM uses
    doc: str


def _predefined() -> dict[str, PredefinedValue]:
    values = [
        PredefinedValue("EAST_WEST", Type.AXIS, 1, "axis: the joint turns about the east-west line"),
        PredefinedValue("NORTH_SOUTH", Type.AXIS, 2, "axis: the joint turns about the north-south line"),
        PredefinedValue("UP_DOWN", Type.AXIS, 3, "axis: the joint turns about the vertical"),
        PredefinedValue("EAST", Type.DIR, 4, "direction +x"),
        PredefinedValue("WEST", Type.DIR, 5, "direction -x"),
        PredefinedValue("NORTH", Type.DIR, 6, "direction +y"),
        PredefinedValue("SOUTH", Type.DIR, 7, "direction -y"),
        PredefinedValue("UP", Type.DIR, 8, "direction +z"),
        PredefinedValue("DOWN", Type.DIR, 9, "direction -z"),
    ]
    values += [
        PredefinedValue(f"EVENT_PROXIMITY_{k}", Type.EVENT, k,
                        f"event: physical proximity sensor {k} sees an object")
        for k in range(8)
    ]
    return {value.name: value for value in values}


PREDEFINED_VALUES: dict[str, PredefinedValue] = _predefined()

INT8_MIN = -128
INT8_MAX = 127
