"""Output formats: the C file compiles, the listing names what the bytes mean, the role table."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from rdcd_core.compiler.render import render_c, render_listing, to_json
from rdcd_core.compiler.roletable import build_role_table


@pytest.mark.skipif(shutil.which("gcc") is None, reason="no C compiler")
def test_c_output_compiles(obstacle, tmp_path):
    source = tmp_path / "program.c"
    source.write_text(render_c(obstacle, "obstacle_avoidance.rdcd"))
    done = subprocess.run(["gcc", "-std=c99", "-Wall", "-Werror", "-c", str(source), "-o",
                           str(tmp_path / "program.o")], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr


def test_listing_shows_every_fragment_and_the_budget(obstacle):
    listing = render_listing(obstacle)
    for fragment in obstacle.fragments:
        assert f"fragment {fragment.name}" in listing
    assert "embedded body" in listing and "Reverse@RightWheel" in listing
    assert f"total {obstacle.total_bytes} bytes" in listing


def test_json_round_trips_the_program(obstacle):
    data = to_json(obstacle)
    assert [bytes(f["bytes"]) for f in data["fragments"]] == [f.code for f in obstacle.fragments]
    assert data["max_fragment_bytes"] == max(f["size"] for f in data["fragments"])


def test_role_table_applications_and_instance_of(check):
    model = check("abstract role W { self.center_position == EAST_WEST;\n"
                  "  command c() { self.assumeRole(M, { self.sleep(); }); } }\n"
                  "role A extends W { self.y() > 0; }\nrole B extends W { self.y() < 0; }\n"
                  "role M modifies W { }\n"
                  "role X { connected_role(DOWN, W) > 0; }\ndeployment { A, B, X }").model
    table = build_role_table(model)
    assert [(e.id, e.name, e.kind) for e in table.entries] == [
        (1, "A", "concrete"), (2, "B", "concrete"), (3, "X", "concrete"), (4, "W", "abstract"),
        (5, "M@A", "application"), (6, "M@B", "application")]
    assert table.entries[4].instance_of == [5, 1, 4]
    assert table.entries[0].instance_of == [1, 4]
