"""The simulation report (JSON) and its one-screen text summary."""

from __future__ import annotations

import math
import re
from collections import Counter
from typing import TYPE_CHECKING, Any

from rdcd_core.compiler.program import CompiledProgram
from sim import state_report, structure_report
from vm.lattice.joint import wrap
from vm.lattice.structure import AXIS_NAMES, Structure
from vm.roles import NO_ROLE, RoleTable

if TYPE_CHECKING:
    from sim.run import Options, RunResult


def role_name(roles: RoleTable, role: int) -> str | None:
    return None if role == NO_ROLE else roles.name(role)


def locate(program: CompiledProgram, code: bytes, pc: int | None) -> tuple[str | None, int | None]:
    """The fragment that ``code`` is (or, for a handler or command body, lies in) and ``pc`` as an
    offset in that fragment; (None, pc) when no fragment holds it."""
    fragments = list(program.fragments)
    for fragment in fragments:
        if bytes(fragment.code) == code:
            return fragment.name, pc
    for fragment in fragments:
        start = bytes(fragment.code).find(code) if code else -1
        if start >= 0:
            return fragment.name, None if pc is None else start + pc
    return None, pc


def source_line(program: CompiledProgram, fragment: str | None, pc: int | None) -> int | None:
    """The source line of the instruction at ``pc`` of ``fragment`` (None when unknown)."""
    if fragment is None or pc is None:
        return None
    entries = next((f.source_map for f in program.fragments if f.name == fragment), [])
    line = next((e.line for e in entries if e.offset <= pc < e.offset + e.size), 0)
    return line or None


def source_of(program: CompiledProgram, code: bytes, pc: int | None) -> dict[str, Any]:
    """Where an instruction of ``code`` at ``pc`` is: its fragment, the offset in it and the
    program's source line (the parts that are known)."""
    fragment, offset = locate(program, bytes(code), pc)
    out: dict[str, Any] = {}
    if fragment is None:
        return out
    out["fragment"], out["pc"] = fragment, offset
    lines = dict(program.fragment(fragment).source_lines)
    if offset in lines and lines[offset]:
        out["line"] = lines[offset]
    return out


def _errors(program: CompiledProgram, rt: Any) -> list[dict[str, Any]]:
    """A module's errors; those of program runs also name the fragment, the pc in it and the
    source line (an out-of-range value or a zero divisor says which line computed it)."""
    places = {(e.t, e.message): locate(program, e.code, e.pc) for e in getattr(rt, "run_errors", [])}
    out = []
    for t, message in rt.errors:
        entry: dict[str, Any] = {"t": round(t, 3), "message": message}
        if (t, message) in places:
            entry["fragment"], entry["pc"] = places[(t, message)]
            line = source_line(program, entry["fragment"], entry["pc"])
            if line is not None:
                entry["line"] = line
        out.append(entry)
    return out


def run_options(program: CompiledProgram, structure: Structure, options: Options) -> dict[str, Any]:
    """What a run is made of, as its report names it. The debugger sends the same fields with each
    stop, so an editor can tell whether a replay shows a run like the one being debugged."""
    return {
        "world": options.world,
        "vm": options.vm,
        "target": program.target,
        "config": structure.name or options.config,
        "entry": structure.entry,
        "obstacle": options.obstacle,
        "duration_s": options.duration,
        "seed": options.seed,
        "packet_loss": options.packet_loss,
    }


def build_report(program: CompiledProgram, structure: Structure, roles: RoleTable, options: Options,
                 run: RunResult, wall_s: float, start: Structure | None = None) -> dict[str, Any]:
    """``structure``: the structure at the end of the run; ``start``: at its start (the same if
    not given). A module attached during the run starts where it was attached."""
    start = structure if start is None else start
    modules = []
    for mid in sorted(run.runtimes):
        spec = start.modules.get(mid) or structure.modules.get(mid)
        rt = run.runtimes[mid]
        final_role = role_name(roles, rt.role)
        modules.append({
            "id": mid,
            "lattice": list(spec.position) if spec else None,
            "orientation": AXIS_NAMES[spec.axis] if spec else None,
            **structure_report.module_fields(structure, mid),
            "final_role": final_role,
            **state_report.module_fields(program, rt, final_role),
            "role_history": [[round(t, 3), role_name(roles, r)] for t, r in rt.role_history],
            "errors": _errors(program, rt),
        })
    tracking = run.tracking
    detections = sum(1 for e in run.events if e["kind"] == "handler")
    report: dict[str, Any] = {
        **run_options(program, structure, options),
        "wall_time_s": round(wall_s, 3),
        "real_time_factor": round(options.duration / wall_s, 2) if wall_s > 0 else None,
        "modules": modules,
        **state_report.report_fields(program, modules, options.duration),
        "fragments": [{"name": f.name, "size": f.size} for f in program.fragments],
        "messages": {k: run.counters.get(k, 0) for k in ("sent", "delivered", "dropped")}
        | {"not_sent_over_limit": run.counters.get("oversize", 0)},
        "events": run.events,
        **structure_report.report_fields(structure, run.events),
        "trajectory": tracking.trajectory if tracking else [],
        "obstacles": [{"kind": b.kind, "x": b.x, "y": b.y, "w": b.w, "l": b.l} for b in run.boxes],
        "obstacle_detections": detections,
        "min_obstacle_distance_m": (round(tracking.min_distance, 4)
                                    if tracking and tracking.min_distance is not None else None),
        "collided": tracking.collided if tracking else None,
        "module_start_xy": {str(k): [round(v, 4) for v in xy] for k, xy in run.start_positions.items()},
    }
    return report


def heading_change(trajectory: list[list[float]]) -> float | None:
    """Final heading minus initial heading, in -180..180 degrees."""
    if len(trajectory) < 2:
        return None
    return wrap(trajectory[-1][3] - trajectory[0][3])


def distance(trajectory: list[list[float]]) -> float | None:
    """Path length of the robot centre in metres."""
    if len(trajectory) < 2:
        return None
    return sum(math.dist(a[1:3], b[1:3]) for a, b in zip(trajectory, trajectory[1:], strict=False))


def summary(report: dict[str, Any]) -> str:
    roles = Counter("taken away" if "final_lattice" in m and m["final_lattice"] is None
                    else m["final_role"] or "none" for m in report["modules"])
    sizes = ", ".join(f"{f['name']} {f['size']}" for f in report["fragments"])
    total = sum(f["size"] for f in report["fragments"])
    lines = [
        f"{report['config']} in the {report['world']} world{_vm(report)}, obstacle {report['obstacle']}, "
        f"{report['duration_s']:g} s, seed {report['seed']}",
        "roles: " + ", ".join(f"{n} × {name}" for name, n in sorted(roles.items())),
        f"fragments: {len(report['fragments'])}, {total} bytes ({sizes})",
        f"messages: {report['messages']['sent']} sent, {report['messages']['delivered']} delivered, "
        f"{report['messages']['dropped']} dropped",
        *_not_sent_lines(report),
        f"obstacle detections: {report['obstacle_detections']}",
        *state_report.summary_lines(report),
    ]
    changed = structure_report.summary_line(report)
    if changed:
        lines.append(changed)
    roles_after = structure_report.roles_line(report)
    if roles_after:
        lines.append(roles_after)
    traj = report["trajectory"]
    if traj:
        (x0, y0), (x1, y1) = traj[0][1:3], traj[-1][1:3]
        lines.append(f"distance: {distance(traj):.2f} m travelled, net ({x1 - x0:+.2f}, {y1 - y0:+.2f}) m; "
                     f"heading change {heading_change(traj):+.1f}°")
        if report["min_obstacle_distance_m"] is not None:
            lines.append(f"closest to an obstacle: {report['min_obstacle_distance_m']:.3f} m; "
                         f"collided: {'yes' if report['collided'] else 'no'}")
    errors = sum(len(m["errors"]) for m in report["modules"])
    if errors:
        lines.append(f"runtime errors: {errors} (see the report)")
        lines += _error_lines(report)
    lines.append(f"real-time factor: {report['real_time_factor']}× ({report['wall_time_s']:.1f} s wall)")
    return "\n".join(lines)


def _not_sent_lines(report: dict[str, Any]) -> list[str]:
    """Packets over the IR packet limit: the robot's links would not carry them (docs/vm.md)."""
    events = [e for e in report["events"] if e["kind"] == "packet_not_sent"]
    if not events:
        return []
    first = events[0]
    detail = first["detail"]
    tries = report["messages"].get("not_sent_over_limit", len(events))
    return [f"not sent, over the {detail['limit']}-byte IR packet limit: {tries} packets (tries included), "
            f"the first at {first['t']:g} s by module {first['module']}, a {detail['type']} packet of "
            f"{detail['bytes']} bytes; the ATRON would not receive it"]


def _vm(report: dict[str, Any]) -> str:
    """The VM profile and the compile target, when they are not both the default."""
    vm, target = report.get("vm", "default"), report.get("target", "default")
    if vm == target == "default":
        return ""
    return f" ({vm} VM" + ("" if target == vm else f", program compiled for the {target} target") + ")"


MAX_ERROR_LINES = 6
_RUN_PREFIX = re.compile(r"^program \S+: (pc \d+: )?")


def _error_lines(report: dict[str, Any]) -> list[str]:
    """The first errors, one line per module and message; those of program runs with the
    fragment and the pc in it."""
    seen: dict[tuple[Any, ...], int] = {}
    for m in report["modules"]:
        for e in m["errors"]:
            key = (m["id"], e.get("fragment", ""), e.get("pc"), e["message"], "fragment" in e, e.get("line"))
            seen[key] = seen.get(key, 0) + 1
    lines = []
    for (mid, fragment, pc, message, ran, line), n in list(seen.items())[:MAX_ERROR_LINES]:
        times = f" (×{n})" if n > 1 else ""
        if ran:
            message = _RUN_PREFIX.sub("", message)  # the pc in it counts from a handler's own start
            where = f", fragment {fragment or '?'}, pc {pc if pc is not None else '?'}"
            where += f", line {line}" if line is not None else ""
        else:
            where = ""
        lines.append(f"  module {mid}{where}: {message}{times}")
    if len(seen) > MAX_ERROR_LINES:
        lines.append(f"  … and {len(seen) - MAX_ERROR_LINES} more")
    return lines
