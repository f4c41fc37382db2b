"""Build time of the documentation site under ``mkdocs build --strict``, with its code blocks
coloured (mkdocs.yml as it is) and without (the same configuration less ``pymdownx.highlight`` and
``pymdownx.inlinehilite``: the site before issue 26), alternated so that both meet the same load.

    python benchmarks/site_build.py [--runs 6]

Prints each build's wall and CPU time (the build's process: user + system, steadier than wall time
on a shared machine) and the medians of each configuration. Needs ``.[docs]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HIGHLIGHT_LINES = ("pymdownx.highlight", "use_pygments", "pygments_lang_class", "pymdownx.inlinehilite")


def plain_config(folder: Path) -> Path:
    """mkdocs.yml without the highlighter, in ``folder``, reading the repository's docs/."""
    lines = [line for line in (ROOT / "mkdocs.yml").read_text(encoding="utf-8").splitlines()
             if not any(key in line for key in HIGHLIGHT_LINES)]
    lines = [f"docs_dir: {ROOT / 'docs'}" if line.startswith("docs_dir:") else line for line in lines]
    path = folder / "mkdocs-plain.yml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def build(config: Path, out: Path) -> tuple[float, float]:
    """(wall, CPU) seconds of one build, in a new process as CI runs it."""
    start, cpu = time.perf_counter(), _children_cpu()
    subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet", "-f", str(config),
                    "-d", str(out)], cwd=ROOT, check=True, env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})
    return time.perf_counter() - start, _children_cpu() - cpu


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=6)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        configs = {"coloured": ROOT / "mkdocs.yml", "plain": plain_config(folder)}
        times: dict[str, list[tuple[float, float]]] = {name: [] for name in configs}
        for run in range(args.runs):
            for name, config in configs.items():
                wall, cpu = build(config, folder / name)
                times[name].append((wall, cpu))
                print(f"run {run + 1} {name}: {wall:.2f} s wall, {cpu:.2f} s CPU", flush=True)
    medians = {name: [statistics.median(t[i] for t in values) for i in (0, 1)]
               for name, values in times.items()}
    for name, (wall, cpu) in medians.items():
        walls = [t[0] for t in times[name]]
        print(f"{name}: median {wall:.2f} s wall ({min(walls):.2f}-{max(walls):.2f}), {cpu:.2f} s CPU")
    for i, what in enumerate(("wall", "CPU")):
        print(f"coloured / plain, median {what}: {medians['coloured'][i] / medians['plain'][i] - 1:+.1%}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
