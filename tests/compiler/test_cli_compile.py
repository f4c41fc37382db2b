"""``rdcd compile``: formats, output file, exit statuses."""

from __future__ import annotations

import json
from pathlib import Path

from rdcd_core.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
OBSTACLE = str(EXAMPLES / "obstacle_avoidance.rdcd")


def test_json_format(capsys):
    assert main(["compile", "--format", "json", OBSTACLE]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"target", "packet_budget", "total_bytes", "max_fragment_bytes", "fragments",
                         "roles", "injection"}
    assert data["packet_budget"] == 50 and data["target"] == "default"
    assert data["total_bytes"] == sum(f["size"] for f in data["fragments"]) <= 200
    assert len(data["fragments"]) <= 7 and data["max_fragment_bytes"] <= 43
    for fragment in data["fragments"]:
        assert set(fragment) == {"name", "kind", "role", "size", "bytes", "source"}
        assert len(fragment["bytes"]) == fragment["size"]
        assert fragment["source"]["line"] >= 1
    assert data["injection"] == [f["name"] for f in data["fragments"]]
    assert {r["name"] for r in data["roles"]} >= {"RightWheel", "LeftWheel", "Axle", "Wheel"}


def test_listing_names_operands_and_lines(capsys):
    assert main(["compile", OBSTACLE]) == 0
    out = capsys.readouterr().out
    assert "SET_ROLE_NOTIFY RightWheel" in out
    assert "CONNECTED_DOWN_ROLE Wheel" in out
    assert "EVENT_PROXIMITY_5" in out and "; line " in out
    assert "/43 program bytes" in out and "injection:" in out


def test_c_format_to_file(tmp_path, capsys):
    target = tmp_path / "out.c"
    assert main(["compile", "--format", "c", "-o", str(target), OBSTACLE]) == 0
    text = target.read_text()
    assert "const uint8_t rdcd_discover_RightWheel_LeftWheel[" in text
    assert "int rdcd_instance_of(uint8_t role, uint8_t of)" in text
    assert "RDCD_INJECTION_COUNT" in text
    assert capsys.readouterr().out == ""


def test_errors_exit_1_with_diagnostics(tmp_path, capsys):
    bad = tmp_path / "bad.rdcd"
    bad.write_text("role A extends Missing { }\ndeployment { A }\n")
    assert main(["compile", str(bad)]) == 1
    captured = capsys.readouterr()
    assert "error[E102]" in captured.err and captured.out == ""


def test_missing_file_and_non_utf8_exit_2(tmp_path, capsys):
    assert main(["compile", str(tmp_path / "nope.rdcd")]) == 2
    assert "no such file" in capsys.readouterr().err
    binary = tmp_path / "bin.rdcd"
    binary.write_bytes(b"\xff\xfe\x00role")
    assert main(["compile", str(binary)]) == 2
    err = capsys.readouterr().err
    assert "not UTF-8" in err and len(err.strip().splitlines()) == 1


def test_strict_isa_refuses_extensions(tmp_path, capsys):
    source = tmp_path / "ext.rdcd"
    source.write_text("role A { self.x() + self.y() > 0; }\ndeployment { A }\n")
    assert main(["compile", str(source)]) == 0
    capsys.readouterr()
    assert main(["compile", "--strict-isa", str(source)]) == 1
    assert "E605" in capsys.readouterr().err
    assert main(["compile", "--target", "original", str(source)]) == 1
    err = capsys.readouterr().err
    assert "error[E605]: in role A: " in err and "ADD, which the original target does not run" in err


def test_strict_isa_is_the_original_target(capsys):
    outputs = []
    for options in (["--target", "original"], ["--strict-isa"]):
        assert main(["compile", "--format", "json", *options, OBSTACLE]) == 0
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1] and json.loads(outputs[0])["target"] == "original"


def test_target_original_through_the_real_cli(tmp_path):
    import subprocess
    import sys

    out = tmp_path / "program.c"
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "compile", "--target", "original",
                           "--format", "c", "-o", str(out), OBSTACLE], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    text = out.read_text()
    assert "static void dcd_action(USSRONLY(USSREnv *env))" in text
    snake = str(EXAMPLES / "snake_wave.rdcd")
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", "--target", "original", snake],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and "warning[W604]: in role Head" in done.stdout, done.stdout
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", snake], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0 and "W604" not in done.stdout
    done = subprocess.run([sys.executable, "-m", "rdcd_core", "check", "--target", "firmware", snake],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "invalid choice" in done.stderr


def test_max_packet_changes_the_split(capsys):
    assert main(["compile", "--format", "json", "--max-packet", "30", OBSTACLE]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["packet_budget"] == 30 and len(data["fragments"]) > 5
