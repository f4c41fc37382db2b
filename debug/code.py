"""The program's code as the debugger sees it: source lines of every instruction (the compiler's
source maps), statement starts, breakpoint locations, the fragment a running piece of code lies
in, and addresses for the disassembly view.

A location is (fragment index, offset in the fragment). Code that runs is a fragment's bytes or
a handler / command body embedded in one; ``places(code)`` gives every fragment offset where the
running bytes lie, so a breakpoint on a body's line hits when the body runs.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass

from rdcd_core.compiler.program import CompiledProgram
from vm.isa.disassembler import disassemble

ADDRESS_STRIDE = 0x10000  # fragment i's byte k has the address i * ADDRESS_STRIDE + k


@dataclass(frozen=True)
class Method:
    role: str
    name: str
    lines: tuple[int, int]  # first and last source line (1-based)


class CodeIndex:
    def __init__(self, program: CompiledProgram, methods: list[Method] | None = None) -> None:
        self.program = program
        self.fragments = program.fragments
        self.methods = methods or []
        self._maps: list[tuple[list[int], list[int]]] = []
        self.statements: list[set[int]] = []  # per fragment: offsets where a statement starts
        self.code_lines: set[int] = set()
        self.body_starts: list[set[int]] = []  # per fragment: offsets where an embedded body starts
        for fragment in self.fragments:
            entries = sorted((e.offset, e.line) for e in fragment.source_map)
            self._maps.append(([o for o, _ in entries], [line for _, line in entries]))
            starts, previous = set(), None
            for offset, line in entries:
                if line and line != previous:
                    starts.add(offset)
                    self.code_lines.add(line)
                previous = line or previous
            bodies = set()
            for d in disassemble(fragment.code):
                if d.name == "HANDLE_EVENT" and len(d.operands) == 3:
                    bodies.add(d.operands[1])
                elif d.name == "INSTALL_COMMAND" and len(d.operands) == 4:
                    bodies.add(d.operands[2])
            self.body_starts.append(bodies)
            self.statements.append(starts | bodies)
        self._places: dict[bytes, tuple[tuple[int, int], ...]] = {}

    # ---- where code lies -------------------------------------------------------------------
    def places(self, code: bytes) -> tuple[tuple[int, int], ...]:
        """(fragment index, base offset) of every place the running ``code`` lies in."""
        found = self._places.get(code)
        if found is None:
            whole = tuple((i, 0) for i, f in enumerate(self.fragments) if f.code == code)
            if whole:
                found = whole
            else:
                spots = []
                for i, fragment in enumerate(self.fragments):
                    at = fragment.code.find(code) if code else -1
                    while at >= 0:
                        spots.append((i, at))
                        at = fragment.code.find(code, at + 1)
                found = tuple(spots)
            self._places[code] = found
        return found

    def locate(self, code: bytes, pc: int) -> tuple[int, int] | None:
        """The location of byte ``pc`` of ``code`` (the first place it lies in), or None."""
        places = self.places(code)
        return (places[0][0], places[0][1] + pc) if places else None

    def line(self, index: int, offset: int) -> int:
        """The source line of the instruction at ``offset`` (the nearest line before it if it has
        none), or 0."""
        offsets, lines = self._maps[index]
        i = bisect_right(offsets, offset) - 1
        while i >= 0 and not lines[i]:
            i -= 1
        return lines[i] if i >= 0 else 0

    def line_of(self, code: bytes, pc: int) -> int:
        where = self.locate(code, pc)
        return self.line(*where) if where else 0

    def is_statement(self, code: bytes, pc: int) -> bool:
        return any(base + pc in self.statements[i] for i, base in self.places(code))

    # ---- breakpoints -----------------------------------------------------------------------
    def line_locations(self, line: int) -> list[tuple[int, int]]:
        """The statement starts on ``line``: where a breakpoint on it stops."""
        out = []
        for i in range(len(self.fragments)):
            for offset in sorted(self.statements[i]):
                if self.line(i, offset) == line:
                    out.append((i, offset))
        return out

    def nearest_code_line(self, line: int) -> int | None:
        """The first line with code at or after ``line``, else the last one before it."""
        after = [n for n in self.code_lines if n >= line]
        if after:
            return min(after)
        return max(self.code_lines) if self.code_lines else None

    def method(self, text: str) -> Method | None:
        role, _, name = text.strip().partition(".")
        return next((m for m in self.methods if m.role == role and m.name == name), None)

    def method_locations(self, method: Method) -> list[tuple[int, int]]:
        """Where a run of ``method`` begins: in each fragment, the bodies (handlers, commands)
        written in its lines, or else the first statement of its lines."""
        first, last = method.lines
        out = []
        for i in range(len(self.fragments)):
            inside = sorted(o for o in self.statements[i] if first <= self.line(i, o) <= last)
            if not inside:
                continue
            bodies = [(i, o) for o in inside if o in self.body_starts[i]]
            # a command or handler written in the method runs as its own body: its start, not the
            # instruction that installs it, is where the method begins to run
            out += bodies or [(i, inside[0])]
        return out

    # ---- addresses -------------------------------------------------------------------------
    @staticmethod
    def address(index: int, offset: int) -> str:
        return f"0x{index * ADDRESS_STRIDE + offset:x}"

    @staticmethod
    def parse_address(text: str) -> tuple[int, int] | None:
        try:
            value = int(text, 0)
        except (TypeError, ValueError):
            return None
        return (value // ADDRESS_STRIDE, value % ADDRESS_STRIDE) if value >= 0 else None
