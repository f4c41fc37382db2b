"""Finding the files the repository's text refers to that the repository does not contain."""

from __future__ import annotations

import re
import subprocess
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# Folders of this repository: a path that starts with one of them names a file of ours.
TOP = ("rdcd_core", "vm", "sim", "server", "tests", "docs", "examples", "benchmarks", "tools",
       "vscode-extension", "experiments", ".ci")
OURS = re.compile(r"(?<![\w./-])((?:" + "|".join(re.escape(t) for t in TOP) + r")/[\w./-]*[\w/])")
# Documents of the team that wrote this project, which its users do not have: named bare or under
# spec/ or shared/, they are dangling references wherever they appear.
FOREIGN = re.compile(r"(?<![\w.-])(?:(?:\.\./)*(?:shared|spec)/[\w./-]*\w"
                     r"|(?<![/\w-])(?:DESIGN|dcd-vm|atron|language)\.md)")
SKIP_SUFFIXES = (".png", ".jpg", ".gif", ".ico", ".vsix", ".woff", ".woff2", ".lock")
SKIP_NAMES = ("package-lock.json",)
# Generated bundles carry their dependencies' text (three.js), not references of ours; the tests of
# the scan hold dangling references on purpose.
SKIP_FILES = ("sim/replay/viewer.js", "tests/docs/test_references.py")
PLACEHOLDER = re.compile(r"[A-Z][A-Z_]*(\.\w+)?")  # benchmarks/NAME.py, OUT/runs/KEY.json


def tracked_text_files() -> Iterator[tuple[str, str]]:
    names = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    for name in names.decode().split("\0"):
        if (not name or name.endswith(SKIP_SUFFIXES) or name.rsplit("/", 1)[-1] in SKIP_NAMES
                or name in SKIP_FILES or not (ROOT / name).is_file()):
            continue
        try:
            yield name, (ROOT / name).read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue


def ignored(path: str) -> bool:
    """A path git ignores: an output the project writes (a .vsix, test artifacts), not a source."""
    return subprocess.run(["git", "check-ignore", "-q", "--no-index", path], cwd=ROOT).returncode == 0


def exists(path: str) -> bool:
    path = path.rstrip(".")  # the end of a sentence
    return (ROOT / path).exists() or ignored(path)


def dangling(name: str, text: str) -> Iterator[tuple[int, str]]:
    """(line, reference) of every reference in ``text`` (the file ``name``) to a missing file."""
    here = (ROOT / name).parent
    for number, line in enumerate(text.splitlines(), 1):
        for match in FOREIGN.finditer(line):
            ref = match.group(0)
            # a page of this site named by the site's own files (docs/, mkdocs.yml) is ours
            site = name.startswith("docs/") or name == "mkdocs.yml"
            if "/" in ref or not (site and ((here / ref).is_file() or (ROOT / "docs" / ref).is_file())):
                yield number, ref
        for match in OURS.finditer(line):
            path = match.group(1)
            if PLACEHOLDER.fullmatch(path.rstrip("/").rsplit("/", 1)[-1]):
                continue
            if not exists(path) and not here.joinpath(path).exists():
                yield number, path
