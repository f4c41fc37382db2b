"""Where code comes from: a slot's bytes and pc → (fragment, offset) → source line.

Programs arrive whole (a fragment's code); handlers and user commands are pieces of a fragment
(their bodies are embedded in it), so a piece is found by searching the fragments' code.
"""

from __future__ import annotations

from bisect import bisect_right

from rdcd_core.compiler.program import CompiledProgram


class SourceIndex:
    def __init__(self, program: CompiledProgram, text: str) -> None:
        self.fragments = program.fragments
        # lines as the compiler counts them (rdcd_core.source.LineIndex: only \n ends a line)
        self.lines = [line.removesuffix("\r") for line in text.split("\n")]
        if self.lines and self.lines[-1] == "" and text.endswith("\n"):
            self.lines.pop()
        self._found: dict[bytes, tuple[int, int] | None] = {}
        self._maps = []
        for fragment in self.fragments:
            entries = sorted((e.offset, e.line) for e in fragment.source_map)
            self._maps.append(([o for o, _ in entries], [line for _, line in entries]))

    def locate(self, code: bytes, pc: int, within: int | None = None) -> tuple[tuple[int, int] | None, int]:
        """((fragment index, offset in it), source line or -1) of byte ``pc`` of ``code``.
        ``within``: the fragment the code is known to come from (one body can lie in several)."""
        code = bytes(code)
        at = self.fragments[within].code.find(code) if within is not None and code else -1
        start = (within, at) if at >= 0 else self.start(code)
        if start is None:
            return None, -1
        index, base = start
        return (index, base + pc), self.line(index, base + pc)

    def line(self, index: int, offset: int) -> int:
        offsets, lines = self._maps[index]
        i = bisect_right(offsets, offset) - 1
        while i >= 0 and not lines[i]:  # an instruction without a line: the nearest before it
            i -= 1
        return lines[i] if i >= 0 else -1

    def fragment_name(self, where: tuple[int, int] | None) -> str:
        return self.fragments[where[0]].name if where else "?"

    def start(self, code: bytes) -> tuple[int, int] | None:
        if code not in self._found:
            whole = next((i for i, f in enumerate(self.fragments) if f.code == code), None)
            found = (whole, 0) if whole is not None else None
            for i, fragment in enumerate(self.fragments):
                at = fragment.code.find(code) if code and found is None else -1
                if at >= 0:
                    found = (i, at)
            self._found[code] = found
        return self._found[code]
