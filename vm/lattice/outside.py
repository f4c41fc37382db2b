"""Outside changes: what a person does to a running robot at a given time (docs/simulator.md
"Outside changes") — detach a module, attach a new one on a free cell, stop a module for good,
jam a connector (its latch no longer moves: it neither closes nor opens), or make a connector's
latch not close the next time it is asked to (once: a latch that does not close).

Text form (``rdcd simulate --change``, one change per option or per line of a file; ``#``
starts a comment):

    TIME:detach ID                 e.g.  20s:detach 3
    TIME:attach ID at X,Y,Z [AXIS] [rot R] [mirrored]      5s:attach 8 at 1,1,0 EW
    TIME:stop ID                   30s:stop 4
    TIME:jam ID CONNECTOR          0s:jam 2 0      (for good)
    TIME:fail ID CONNECTOR         0s:fail 2 0     (its next latch does not close, once)

TIME is seconds, with or without ``s``. The axis of a cell follows from its parity and may be
left out (if given it must agree); ``rot`` (0..3) and ``mirrored`` are the mount
(sim/configs/README.md). ``parse`` checks the syntax only (``ChangeError``, one line);
``validate`` checks a list against a structure and the run's duration.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from vm import navigation
from vm.lattice.mount import Mount

Vec = tuple[int, int, int]
KINDS = ("detach", "attach", "stop", "jam", "fail")
MAX_CHANGES = 1000

_NUMBER = r"[0-9]+(?:\.[0-9]*)?"
_PATTERN = re.compile(
    rf"\s*(?P<t>{_NUMBER})\s*s?\s*:\s*(?P<kind>[a-z]+)\s+(?P<id>-?[0-9]{{1,9}})"
    r"(?:\s+at\s+(?P<cell>-?[0-9]{1,4}\s*,\s*-?[0-9]{1,4}\s*,\s*-?[0-9]{1,4}))?"
    r"(?P<rest>(?:\s+[A-Za-z0-9_]+)*)\s*")


class ChangeError(ValueError):
    """An outside change that cannot be used; the message is one line."""


@dataclass(frozen=True)
class OutsideChange:
    t: float
    kind: str  # one of KINDS
    module: int
    cell: Vec | None = None  # attach
    axis: int | None = None  # attach
    mount: Mount = Mount()
    text: str = ""  # as written
    connector: int | None = None  # jam, fail: the physical connector 0..7

    def describe(self) -> str:
        where = f" at {','.join(map(str, self.cell))}" if self.cell else ""
        which = f" {self.connector}" if self.connector is not None else ""
        return f"{self.kind} {self.module}{which}{where}"


def parse(text: str) -> OutsideChange:
    match = _PATTERN.fullmatch(text)
    if match is None:
        raise ChangeError(f"change {text!r}: write TIME:detach ID, TIME:attach ID at X,Y,Z [AXIS] "
                          "[rot R] [mirrored], TIME:stop ID, TIME:jam ID CONNECTOR or "
                          "TIME:fail ID CONNECTOR (e.g. 20s:detach 3)")
    kind = match["kind"]
    if kind not in KINDS:
        raise ChangeError(f"change {text!r}: unknown change {kind!r} (detach, attach, stop, jam or fail)")
    t, module = float(match["t"]), int(match["id"])
    words = match["rest"].split()
    if kind in ("jam", "fail"):
        if match["cell"] or len(words) != 1 or words[0] not in tuple("01234567"):
            raise ChangeError(f"change {text!r}: {kind} takes a module id and a connector 0..7 "
                              f"(e.g. 0s:{kind} 2 0)")
        return OutsideChange(t, kind, module, text=text.strip(), connector=int(words[0]))
    if kind != "attach":
        if match["cell"] or words:
            raise ChangeError(f"change {text!r}: {kind} takes only a module id")
        return OutsideChange(t, kind, module, text=text.strip())
    if not match["cell"]:
        raise ChangeError(f"change {text!r}: attach needs a cell: attach ID at X,Y,Z")
    cell = tuple(int(c) for c in match["cell"].split(","))
    axis = navigation.axis_for_position(*cell)
    if axis is None:
        raise ChangeError(f"change {text!r}: {match['cell']} is not a lattice cell (NS: x, y, z even; "
                          "EW: x, y odd, z even; UD: y, z odd, x even)")
    rotation, mirrored = 0, False
    i = 0
    while i < len(words):
        word = words[i]
        if word.upper() in navigation.AXIS_BY_NAME:
            if navigation.AXIS_BY_NAME[word.upper()] != axis:
                raise ChangeError(f"change {text!r}: the cell {match['cell']} has axis "
                                  f"{navigation.AXIS_NAMES[axis]}, not {word}")
        elif word == "mirrored":
            mirrored = True
        elif word == "rot" and i + 1 < len(words) and words[i + 1] in ("0", "1", "2", "3"):
            rotation = int(words[i + 1])
            i += 1
        else:
            raise ChangeError(f"change {text!r}: unexpected {word!r} (an axis, rot 0..3, mirrored)")
        i += 1
    return OutsideChange(t, kind, module, cell, axis, Mount(rotation, mirrored), text.strip())  # type: ignore[arg-type]


def parse_all(texts: list[str]) -> list[OutsideChange]:
    """Changes from options and file lines (blank lines and ``#`` comments skipped), by time."""
    out = []
    for text in texts:
        for line in text.splitlines() or [text]:
            line = line.split("#", 1)[0]
            if line.strip():
                out.append(parse(line))
    if len(out) > MAX_CHANGES:
        raise ChangeError(f"{len(out)} outside changes: at most {MAX_CHANGES}")
    return sorted(out, key=lambda c: c.t)


def validate(changes: list[OutsideChange], structure: object, duration: float) -> None:
    """Check the changes in order against a copy of ``structure`` (a ``Structure``): missing or
    reused modules, occupied cells, cells no free connector faces, times past the end."""
    from vm.lattice.structure import ModuleSpec, Structure

    assert isinstance(structure, Structure)
    s = structure.copy()
    gone: set[int] = set()
    for c in changes:
        where = f"change {c.text or c.describe()!r}"
        if c.t > duration:
            raise ChangeError(f"{where}: at {c.t:g} s, after the end of the run ({duration:g} s)")
        if c.kind == "attach":
            if c.module in s.modules or c.module in gone:
                raise ChangeError(f"{where}: module {c.module} exists already; a new module needs a new id")
            if not 0 <= c.module <= 10_000:
                raise ChangeError(f"{where}: a module id is 0..10000")
            result = s.add(ModuleSpec(c.module, c.cell, c.axis, c.mount))  # type: ignore[arg-type]
            if not result.ok:
                raise ChangeError(f"{where}: {result.reason}")
            continue
        if c.module not in s.modules:
            gone_text = " (detached before)" if c.module in gone else ""
            raise ChangeError(f"{where}: no module {c.module}{gone_text}")
        if c.kind == "detach":
            result = s.remove(c.module)
            if not result.ok:
                raise ChangeError(f"{where}: {result.reason}")
            gone.add(c.module)
