"""The generated pages are what their tables give: the Module API page from
rdcd_core/module_api.py, the instructions page from vm/isa/opcodes.py, the command-line page from
the argparse parsers. Change a table and forget the page, and this fails."""

from __future__ import annotations

import importlib.util

from rdcd_core.module_api import PRIMITIVES
from tests.conftest import ROOT
from vm.isa.opcodes import INSTRUCTIONS


def _generator():  # noqa: ANN202 - the module docs/gen/generate.py
    spec = importlib.util.spec_from_file_location("docs_generate", ROOT / "docs" / "gen" / "generate.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_committed_pages_are_what_the_tables_give() -> None:
    stale = _generator().stale()
    assert not stale, f"run python docs/gen/generate.py: {', '.join(stale)} differ from their tables"


def test_every_table_row_is_on_its_page() -> None:
    api = (ROOT / "docs" / "module-api.md").read_text(encoding="utf-8")
    for primitive in PRIMITIVES:
        assert f"{primitive.name}` |" in api and primitive.doc.replace("|", "\\|") in api, primitive.name
    isa = (ROOT / "docs" / "instructions.md").read_text(encoding="utf-8")
    for ins in INSTRUCTIONS:
        assert f"| {ins.opcode} | `{ins.name}` |" in isa
        assert f"| {ins.size} | {ins.pops} | {ins.pushes} |" in isa
    cli = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    from rdcd_core.cli import SUBCOMMANDS

    for command in SUBCOMMANDS:
        assert f"\n## rdcd {command}\n" in cli and f"```text\nrdcd {command} " in cli
    for option in ("--packet-budget", "--max-packet", "--check", "--config", "--packet-loss",
                   "--retry-failed",
                   "--debounce-ms"):
        assert f"| `{option}` |" in cli, option
    assert "\n## rdcd-lsp\n" in cli and "randomN-seedS" in cli


def test_a_changed_table_makes_the_page_stale(monkeypatch) -> None:  # noqa: ANN001
    import dataclasses

    import rdcd_core.module_api as api

    generator = _generator()
    changed = (dataclasses.replace(api.PRIMITIVES[0], doc="Something else entirely."), *api.PRIMITIVES[1:])
    monkeypatch.setattr(api, "PRIMITIVES", changed)
    assert "module-api.md" in generator.stale()
