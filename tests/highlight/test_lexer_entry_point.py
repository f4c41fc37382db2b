"""The lexer is found the way other tools find it: through the ``pygments.lexers`` entry point of
the installed package (`pip install -e .`), by name, by file name and by ``pygmentize``."""

from __future__ import annotations

import shutil
import subprocess
import sys
from importlib.metadata import entry_points
from pathlib import Path

import pytest
from pygments.lexers import find_lexer_class_by_name, get_lexer_by_name, get_lexer_for_filename

from rdcd_core.pygments_lexer import RdcdLexer
from tests.conftest import EXAMPLES

REINSTALL = "the installed rdcd has no 'rdcd' Pygments entry point: reinstall it (pip install -e .)"


def test_the_entry_point_names_the_lexer() -> None:
    found = [e for e in entry_points(group="pygments.lexers") if e.name == "rdcd"]
    assert len(found) == 1, REINSTALL
    assert found[0].value == "rdcd_core.pygments_lexer:RdcdLexer"
    assert found[0].load() is RdcdLexer


def test_pygments_finds_it_by_name_and_by_file_name() -> None:
    assert find_lexer_class_by_name("rdcd") is RdcdLexer, REINSTALL
    assert isinstance(get_lexer_by_name("rdcd"), RdcdLexer)
    assert isinstance(get_lexer_for_filename("robot.rdcd"), RdcdLexer)


@pytest.mark.parametrize("command", [["pygmentize"], [sys.executable, "-m", "pygments"]])
def test_pygmentize_colours_an_example(command: list[str]) -> None:
    if command[0] == "pygmentize":
        found = shutil.which("pygmentize", path=str(Path(sys.executable).parent))
        if found is None:
            pytest.skip("no pygmentize script next to this Python")
        command = [found]
    done = subprocess.run([*command, "-l", "rdcd", "-f", "html", str(EXAMPLES / "gradient.rdcd")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert '<span class="kd">role</span>' in done.stdout
    assert '<span class="nb">min</span>' in done.stdout
    assert 'class="err"' not in done.stdout
    # and by the file name alone, as `pygmentize FILE` does
    guessed = subprocess.run([*command, "-f", "html", str(EXAMPLES / "gradient.rdcd")],
                             capture_output=True, text=True, timeout=120)
    assert guessed.returncode == 0 and '<span class="kd">role</span>' in guessed.stdout, guessed.stderr
