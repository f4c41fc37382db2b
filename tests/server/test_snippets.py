"""The VS Code extension's snippets, expanded with their default placeholders, are RDCD that
parses and checks: at the top level, as a role member or as a statement, where each belongs."""

from __future__ import annotations

import json
import re

import pytest

from rdcd_core.frontend import check_text
from tests.server.conftest import ROOT

SNIPPETS = json.loads((ROOT / "vscode-extension" / "snippets" / "rdcd.json").read_text())
PLACEHOLDER = re.compile(r"\$\{(\d+):([^${}]*)\}")
CHOICE = re.compile(r"\$\{\d+\|([^,|]*)[^|]*\|\}")
TABSTOP = re.compile(r"\$\d+")

# Where each snippet is typed, and the program around it ({} is the expansion).
CONTEXT = {
    "Role": "{}\ndeployment {{ Name }}\n",
    "Abstract role": "{}\nrole R extends Name {{ constant name := 1; }}\ndeployment {{ R }}\n",
    "Mixin role": "role Role {{ }}\n{}\ndeployment {{ Role }}\n",
    "Constant": "role A {{ {} startup go() {{ self.setLed(name); }} }}\ndeployment {{ A }}\n",
    "State": "{}\nrole A {{ behavior b() {{ name := name + 1; }} }}\ndeployment {{ A }}\n",
    "Startup method": "role A {{ {} }}\ndeployment {{ A }}\n",
    "Behavior method": "role A {{ {} }}\ndeployment {{ A }}\n",
    "Command method": "role A {{ {} startup go() {{ A.name(); }} }}\ndeployment {{ A }}\n",
    "Command with argument": "role A {{ {} startup go() {{ A.name(3); }} }}\ndeployment {{ A }}\n",
    "Event handler": "role A {{ startup go() {{ {} }} }}\ndeployment {{ A }}\n",
    "Assume role": "role A {{ startup go() {{ {} }} }}\nrole Mixin modifies A {{ }}\ndeployment {{ A }}\n",
    "Gradient behaviour": "state hops := 127;\nrole A {{ {} }}\ndeployment {{ A }}\n",
    "Count behaviour": "state size := 1;\nrole A {{ {} }}\ndeployment {{ A }}\n",
    "Deployment": "role Role {{ }}\n{}\n",
}


def expand(body: list[str]) -> str:
    text = "\n".join(body)
    while PLACEHOLDER.search(text):  # placeholders nest: ${2: extends ${3:Module}}
        text = PLACEHOLDER.sub(lambda m: m.group(2), text)
    text = CHOICE.sub(lambda m: m.group(1), text)
    return TABSTOP.sub("", text)


def test_every_snippet_has_a_context() -> None:
    assert set(SNIPPETS) == set(CONTEXT)


@pytest.mark.parametrize("name", sorted(SNIPPETS))
def test_snippet_expands_to_a_valid_program(name: str) -> None:
    snippet = SNIPPETS[name]
    assert snippet["prefix"] and snippet["description"]
    program = CONTEXT[name].format(expand(snippet["body"]))
    errors = [d for d in check_text(program).diagnostics if d.severity.name == "ERROR"]
    assert not errors, (program, [(d.code, d.message) for d in errors])
