"""Nothing in the repository refers to a file it does not contain: code comments, docstrings,
docs, READMEs, the extension's files. The documents of the team that wrote the project (a spec/
or shared/ folder, DESIGN.md, dcd-vm.md, atron.md, language.md) are not in it: what users need of
them is in docs/, in the project's own words."""

from __future__ import annotations

from tests.docs.references import dangling, tracked_text_files


def test_no_file_refers_to_a_file_the_repository_does_not_have() -> None:
    found = [f"{name}:{line}: {ref}" for name, text in tracked_text_files()
             for line, ref in dangling(name, text)]
    assert found == [], "\n".join(found)


def test_the_scan_finds_what_it_looks_for() -> None:
    text = ("see spec/atron.md and `dcd-vm.md` §10, ../shared/DESIGN.md, sim/no_such_module.py;\n"
            "but docs/diagnostics.md, sim/params.py and vscode-extension/rdcd-0.1.0.vsix (built) exist")
    assert list(dangling("README.md", text)) == [(1, "spec/atron.md"), (1, "dcd-vm.md"),
                                                 (1, "../shared/DESIGN.md"), (1, "sim/no_such_module.py")]


def test_a_bare_page_name_is_ours_only_inside_the_site() -> None:
    assert list(dangling("docs/index.md", "see [the language](language.md)")) == []
    assert list(dangling("sim/run.py", "# see language.md")) == [(1, "language.md")]
