"""How fast is `rdcd check` on a 10,000-line program? Prints figures (target < 1 s, goal 0.3 s).

Usage: python benchmarks/check_speed.py [LINES]
The program is made of renamed copies of the two example programs (roles, mixins, commands,
assumeRole, handlers, connected_role), so every pass of the analysis has work to do.
"""

from __future__ import annotations

import contextlib
import io
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rdcd_core.cli import main  # noqa: E402
from rdcd_core.frontend import check_text  # noqa: E402
from rdcd_core.semantics import analyze  # noqa: E402
from rdcd_core.syntax.parser import parse  # noqa: E402

ROLE_NAMES = ("Wheel", "RightWheel", "LeftWheel", "Reverse", "Axle", "Segment", "Head", "Body")


def _body(path: Path) -> str:
    text = path.read_text(encoding="utf-8")
    return text[:text.index("deployment")]


def generate(lines: int) -> str:
    """A program of about ``lines`` lines made of numbered copies of the examples."""
    unit = _body(ROOT / "examples" / "obstacle_avoidance.rdcd") + \
        _body(ROOT / "examples" / "snake_wave.rdcd")
    pattern = re.compile(r"\b(" + "|".join(ROLE_NAMES) + r")\b")
    parts: list[str] = []
    deployed: list[str] = []
    copy = 0
    while sum(p.count("\n") for p in parts) < lines - 2:
        parts.append(pattern.sub(lambda m, c=copy: f"{m.group(1)}{c}", unit))
        deployed += [f"{name}{copy}" for name in ("RightWheel", "LeftWheel", "Axle", "Head", "Body")]
        copy += 1
    return "".join(parts) + "deployment { " + ", ".join(deployed) + " }\n"


def _best(function, repeat: int = 3) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def run(lines: int) -> None:
    text = generate(lines)
    program = parse(text).program
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "big.rdcd"
        path.write_text(text, encoding="utf-8")
        parse_time = _best(lambda: parse(text))
        analyze_time = _best(lambda: analyze(program))
        check_time = _best(lambda: check_text(text))
        sink = io.StringIO()

        def cli() -> None:
            with contextlib.redirect_stdout(sink):
                main(["check", str(path)])

        cli_time = _best(cli)
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "rdcd_core", "check", str(path)], cwd=ROOT,
                       capture_output=True, check=False)
        process_time = time.perf_counter() - start
    result = check_text(text)
    print(f"program: {text.count(chr(10))} lines, {len(program.roles)} roles, "
          f"{len(result.diagnostics)} diagnostics")
    print(f"parse:                 {parse_time * 1000:7.1f} ms")
    print(f"analyze:               {analyze_time * 1000:7.1f} ms")
    print(f"check_text:            {check_time * 1000:7.1f} ms")
    print(f"rdcd check in-process: {cli_time * 1000:7.1f} ms")
    print(f"rdcd check subprocess: {process_time * 1000:7.1f} ms (includes interpreter start)")


if __name__ == "__main__":
    run(int(sys.argv[1]) if len(sys.argv) > 1 else 10_000)
