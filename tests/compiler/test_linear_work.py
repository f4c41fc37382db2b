"""Issue 10, hangs and cliffs: the checker's work grows linearly with the size of a program in
each direction that used to be quadratic (invariants of one role, statements of one method, roles
of a document). Work is counted, not timed: the bytecode instructions executed in rdcd_core, for a size
n and for 4n. Linear work gives a ratio up to 4 (less, with fixed costs); quadratic work, 16.
benchmarks/cliffs.py and benchmarks/inlay_hints.py time the full sizes."""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from rdcd_core.frontend import check_text
from rdcd_core.ide.analysis import analyze
from rdcd_core.ide.inlay import fragment_hints

sys.path.insert(0, str(Path(__file__).resolve().parent))
from large_programs import many_errors, many_ifs, many_invariants, many_roles, many_subroles  # noqa: E402

PACKAGE = Path(__file__).resolve().parents[2] / "rdcd_core"
SMALL = 150
LINEAR = 5  # counts are exact: linear work stays under 4 (fixed costs), quadratic nears 16


def instructions_executed(action: Callable[[], object], folder: Path = PACKAGE) -> int:
    """Bytecode instructions run in rdcd_core's code while ``action`` runs (the code of other
    packages is not traced)."""
    count = 0
    prefix = str(folder)

    def local(frame, event, arg):  # type: ignore[no-untyped-def]
        nonlocal count
        if event == "opcode":
            count += 1
        return local

    def calls(frame, event, arg):  # type: ignore[no-untyped-def]
        if not frame.f_code.co_filename.startswith(prefix):
            return None
        frame.f_trace_opcodes = True  # a comprehension's loop is one line, many instructions
        frame.f_trace_lines = False
        return local

    sys.settrace(calls)
    try:
        action()
    finally:
        sys.settrace(None)
    return count


def growth(make: Callable[[int], Callable[[], object]], folder: Path = PACKAGE) -> float:
    make(SMALL)()  # imports, tables and caches outside the count
    return instructions_executed(make(4 * SMALL), folder) / instructions_executed(make(SMALL), folder)


def nonlocal_invariants(n: int) -> str:
    """Invariants the state space cannot decide: each is a test and a jump of its own."""
    return "role Big {\n" + "".join(f"  self.x() != {i % 200 - 100};\n" for i in range(n)) + \
        "}\ndeployment { Big }\n"


CHECKS = {
    "invariants of one role": nonlocal_invariants,
    "if/else in a behaviour": lambda n: many_ifs(n, "behavior"),
    "ifs in a command": lambda n: many_ifs(n, "command", with_else=False),
    "ifs in a startup method (split into fragments)": lambda n: many_ifs(n, "startup", with_else=False),
    "roles with a command each": many_subroles,
    "calls the compiler reports (E604 each)": many_errors,
}


@pytest.mark.parametrize("name", CHECKS)
@pytest.mark.parametrize("folder", ["", "compiler"])
def test_check_work_grows_linearly(name: str, folder: str) -> None:
    """The whole check, and the compiler alone (where the quadratic steps were)."""
    def make(n: int) -> Callable[[], object]:
        text = CHECKS[name](n)
        return lambda: check_text(text)

    assert growth(make, PACKAGE / folder) < LINEAR, name


def test_local_invariants_are_evaluated_once_per_shape(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each local invariant was evaluated over all 768 local states; equal shapes now share it."""
    from rdcd_core.compiler import fold

    counted = {"vectors": 0}
    original = fold._vector

    def counting(*args):  # type: ignore[no-untyped-def]
        counted["vectors"] += 1
        return original(*args)

    monkeypatch.setattr(fold, "_vector", counting)
    counts = []
    for n in (50, 400):
        counted["vectors"] = 0
        check_text(many_invariants(n))
        counts.append(counted["vectors"])
    assert counts[1] <= counts[0] + 60  # the constants differ, the shapes repeat


@pytest.mark.parametrize("generate", [many_roles, many_subroles])
def test_inlay_hint_work_grows_linearly_with_roles(generate: Callable[[int], str]) -> None:
    def make(n: int) -> Callable[[], object]:
        analysis = analyze(generate(n))
        analysis.compiled()
        return lambda: fragment_hints(analysis)

    assert growth(make) < LINEAR
