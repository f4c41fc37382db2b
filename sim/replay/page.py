"""The replay page: one self-contained HTML file (no network, no server) with the recording as
JSON and the viewer (``sim/replay/viewer.js``, built from ``sim/replay/viewer/src`` with three.js)
inline. A Content-Security-Policy allows exactly the page's own script and style (by hash), so it
runs unchanged inside an editor's webview with a strict policy; no eval, no inline handlers.
"""

from __future__ import annotations

import base64
import hashlib
import html
import json
from importlib import resources
from typing import Any

from rdcd_core.compiler.program import CompiledProgram
from sim.replay import encode
from sim.replay.recording import Recording
from vm.lattice.structure import AXIS_NAMES, Structure


def viewer_script() -> str:
    return resources.files("sim.replay").joinpath("viewer.js").read_text(encoding="utf-8")


def viewer_style() -> str:
    return resources.files("sim.replay").joinpath("viewer/src/style.css").read_text(encoding="utf-8")


def replay_data(recording: Recording, program: CompiledProgram, structure: Structure,
                report: dict[str, Any], source_name: str) -> dict[str, Any]:
    from sim import geometry as g
    from sim import params
    from sim.robot import wheel_side

    stored = recording.stored_fragments()
    by_id = {m["id"]: m for m in report["modules"]}
    modules = []
    specs = recording.specs or structure.modules  # every module ever in the world, as it appeared
    for mid in recording.ids or sorted(structure.modules):
        spec = specs[mid]
        entry = by_id.get(mid, {})
        modules.append({"id": mid, "lattice": list(spec.position), "axis": AXIS_NAMES[spec.axis],
                        "wheel": wheel_side(structure, mid) if mid in structure.modules else 0,
                        "final_lattice": entry.get("final_lattice", list(spec.position)),
                        "connectors": [[round(c, 4) for c in g.connector_direction(spec.axis, v)]
                                       for v in range(8)],
                        "pole": list(g.AXIS_VECTORS[spec.axis]),
                        "role_history": entry.get("role_history", []),
                        "final_role": entry.get("final_role"), "fragments": stored.get(mid, []),
                        "final_state": entry.get("final_state", {}),
                        "state_history": entry.get("state_history", []),
                        "state_history_omitted": entry.get("state_history_omitted", 0),
                        "errors": len(entry.get("errors", []))})
    roles = sorted({r.name for r in program.roles})
    return {
        "version": 1,
        "meta": {"program": source_name, "config": report.get("config"), "world": report.get("world"),
                 "obstacle": report.get("obstacle"), "duration_s": report.get("duration_s"),
                 "seed": report.get("seed"), "packet_loss": report.get("packet_loss"),
                 "entry": structure.entry, "sample_hz": recording.hz, "notes": recording.finish_notes(),
                 "messages": report.get("messages"), "collided": report.get("collided")},
        "roles": roles,
        "states": report.get("states", []),
        "modules": modules,
        "obstacles": report.get("obstacles", []),
        "obstacle_height": _obstacle_height(),
        "module_radius": params.MODULE_RADIUS,
        "ring": {"radius": params.RING_RADIUS, "offset": params.RING_AXIAL_OFFSET,
                 "width": params.RING_WIDTH},
        "source": {"name": source_name, "lines": recording.sources.lines},
        "fragments": [{"name": f.name, "kind": f.kind, "role": f.role, "size": f.size,
                       "lines": list(f.source), "pc_lines": [list(p) for p in f.source_lines]}
                      for f in program.fragments],
        "events": recording.events,
        "links": recording.links,
        "poses": encode.poses(recording),
        "packets": encode.packets(recording),
    }


def _obstacle_height() -> float:
    from sim import params

    return params.WALL_HEIGHT


def json_for_script(data: Any) -> str:
    """JSON that cannot end its <script> element or open a comment: <, > and & are escaped."""
    text = json.dumps(data, separators=(",", ":"), ensure_ascii=False)
    return (text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")
            .replace("\u2028", "\\u2028").replace("\u2029", "\\u2029"))


def _hash(text: str) -> str:
    return "'sha256-" + base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode() + "'"


def render_page(data: dict[str, Any]) -> str:
    script, style = viewer_script(), viewer_style()
    # a </script inside the bundle would end the element early (three.js has none; refuse it)
    if "</script" in script.lower():
        raise RuntimeError("the viewer bundle contains '</script'; rebuild it")
    policy = (f"default-src 'none'; script-src {_hash(script)}; style-src {_hash(style)}; "
              "img-src data: blob:; connect-src 'none'; base-uri 'none'; form-action 'none'")
    title = html.escape(f"rdcd replay: {data['meta']['program']} on {data['meta']['config']}")
    return (
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
        f"<meta http-equiv=\"Content-Security-Policy\" content=\"{html.escape(policy, quote=False)}\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        f"<title>{title}</title>\n<style>{style}</style>\n</head><body>\n"
        "<noscript>The replay needs JavaScript and WebGL.</noscript>\n"
        f"<script type=\"application/json\" id=\"rdcd-replay-data\">{json_for_script(data)}</script>\n"
        f"<script>{script}</script>\n</body></html>\n")


def write_page(path: str, recording: Recording, program: CompiledProgram, structure: Structure,
               report: dict[str, Any], source_name: str) -> int:
    """Writes the page atomically; returns its size in bytes."""
    from rdcd_core.outputs import write_atomically

    page = render_page(replay_data(recording, program, structure, report, source_name)).encode("utf-8")
    write_atomically(path, page)
    return len(page)
