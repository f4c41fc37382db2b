// What the timeline marks: detections, role changes, reversals, errors, lost packets and changes of
// the structure (latches, turns, splits, outside changes: the kinds of sim/structure_report.py).
import { ROTATE_CCW, ROTATE_CW } from "./constants.js";

export const MARKER_COLOURS = {
  detection: "#e6a100", role: "#3a78d8", reversal: "#9c4dd8", error: "#d62728", lost: "#ff5a5a",
  structure: "#1b7f3b",
};

// the events that are changes of the structure (a rotation is marked where it starts and ends)
export const STRUCTURE_KINDS = new Set(["connect", "disconnect", "connect_failed", "disconnect_failed",
  "rotation_start", "rotation_end", "rotation_failed", "split", "outside", "outside_failed", "attach", "detach",
  "joint_unmodelled"]);

export function collectMarkers(rec) {
  const out = [];
  const direction = new Map();
  for (const [index, [t, module, kind, , , , text]] of rec.data.events.entries()) {
    if (kind === "handler" || kind === "sensor") out.push({ t, kind: "detection", module, text });
    else if (kind === "role") out.push({ t, kind: "role", module, text });
    else if (kind === "error") out.push({ t, kind: "error", module, text });
    else if (STRUCTURE_KINDS.has(kind)) out.push({ t, kind: "structure", module, text, event: kind, index });
    else if (kind === "command") {
      const sign = text.includes(ROTATE_CCW) ? -1 : text.includes(ROTATE_CW) ? 1 : 0;
      const m = /\((-?\d+)\)/.exec(text);
      const arg = m ? Math.sign(Number(m[1]) || 1) : 1;
      if (sign !== 0) {
        const now = sign * arg;
        const before = direction.get(module);
        if (before !== undefined && before !== now) out.push({ t, kind: "reversal", module, text });
        direction.set(module, now);
      }
    }
  }
  const p = rec.packets;
  for (let i = 0; i < p.count; i++) {
    if (p.dropped[i]) out.push({ t: p.t[i], kind: "lost", module: p.from[i], text: "packet lost" });
  }
  return out;
}
