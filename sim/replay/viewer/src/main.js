// Entry of the replay page (sim/replay/page.py inlines the bundle of this file).
// Test and embedding hook: window.rdcdReplay (see the README of sim/replay/viewer).
import { NO_ROLE_COLOUR } from "./constants.js";
import { decode, lastAtOrBefore, readData, roleAt } from "./data.js";
import { collectMarkers } from "./markers.js";
import { Scene } from "./scene.js";
import { stateAt, stateSection } from "./state.js";
import { buildLayout, drawMarkers, el, fillLegend, formatTime } from "./ui.js";

const EVENT_WINDOW = 1500; // event rows in the list at once (around the current time)
const MODULE_EVENTS = 200; // event rows in a module's panel
const vscode = typeof acquireVsCodeApi === "function" ? acquireVsCodeApi() : null; // eslint-disable-line no-undef

class Replay {
  constructor(rec, ui) {
    this.rec = rec;
    this.ui = ui;
    this.data = rec.data;
    this.duration = this.data.meta.duration_s;
    this.t = 0;
    this.playing = false;
    this.selected = null;
    this.selectedEvent = null;
    this.scene = new Scene(rec, ui.view);
    this.markers = collectMarkers(rec);
    this.eventTimes = Float64Array.from(this.data.events, (e) => e[0]);
    this.listed = { from: 0, to: 0, module: undefined };
    fillLegend(ui.legend, this.scene.roleColour, NO_ROLE_COLOUR);
    this.#wire();
    this.resize();
    drawMarkers(ui.markers, this.markers, this.duration);
    this.seek(0);
  }

  #wire() {
    const ui = this.ui;
    ui.play.addEventListener("click", () => this.toggle());
    ui.slider.addEventListener("input", () => this.seek(Number(ui.slider.value)));
    ui.followBox.addEventListener("change", () => { this.scene.follow = ui.followBox.checked; this.render(); });
    ui.filterBox.addEventListener("change", () => this.#listEvents(true));
    ui.markers.addEventListener("click", (e) => {
      const rect = ui.markers.getBoundingClientRect();
      const t = ((e.clientX - rect.left) / rect.width) * this.duration;
      // a change of the structure under the pointer: its event, with its source line
      const near = this.#structureMarkerNear(t, (4 / Math.max(1, rect.width)) * this.duration);
      if (near) this.showEvent(near.index);
      else this.seek(t);
    });
    let down = null;
    const canvas = this.scene.renderer.domElement;
    canvas.addEventListener("pointerdown", (e) => { down = [e.clientX, e.clientY]; });
    canvas.addEventListener("pointerup", (e) => {
      if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) {
        const id = this.scene.pickAt(e.clientX, e.clientY);
        if (id !== null) this.pick(id);
      }
      down = null;
    });
    for (const list of [ui.events, ui.modulePanel]) {
      list.addEventListener("click", (e) => {
        const row = e.target.closest("li[data-index]");
        if (row) this.showEvent(Number(row.dataset.index));
      });
    }
    window.addEventListener("resize", () => this.resize());
    window.addEventListener("keydown", (e) => {
      if (e.key === " " && e.target === document.body) { e.preventDefault(); this.toggle(); }
    });
    // the camera moved (dragging, or following the robot): draw once in the next frame
    this.scene.controls.addEventListener("change", () => {
      if (this.drawPending || this.playing) return;
      this.drawPending = true;
      requestAnimationFrame(() => { this.drawPending = false; this.render(); });
    });
  }

  #structureMarkerNear(t, within) {
    let best = null;
    for (const marker of this.markers) {
      if (marker.kind !== "structure" || Math.abs(marker.t - t) > within) continue;
      if (!best || Math.abs(marker.t - t) < Math.abs(best.t - t)) best = marker;
    }
    return best;
  }

  resize() {
    const rect = this.ui.view.getBoundingClientRect();
    this.scene.resize(Math.max(1, rect.width), Math.max(1, rect.height));
    drawMarkers(this.ui.markers, this.markers, this.duration);
    this.render();
  }

  render() {
    this.scene.render();
  }

  seek(t) {
    this.t = Math.min(this.duration, Math.max(0, Number(t) || 0));
    this.scene.update(this.t);
    this.ui.slider.value = String(this.t);
    this.ui.clock.textContent = formatTime(this.t);
    this.#listEvents(false);
    this.#showState();
    this.render();
  }

  toggle() {
    this.playing = !this.playing;
    this.ui.play.textContent = this.playing ? "❚❚" : "▶";
    if (!this.playing) return;
    if (this.t >= this.duration) this.seek(0);
    let last = performance.now();
    const frame = (now) => {
      if (!this.playing) return;
      const speed = Number(this.ui.speed.value) || 1;
      this.seek(this.t + ((now - last) / 1000) * speed);
      last = now;
      if (this.t >= this.duration) this.toggle();
      else requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
  }

  // the debugger stopped at time t on module `module` (null: none): the same moment, that module shown
  showMoment(t, module) {
    this.seek(t);
    if (Number.isInteger(module) && this.rec.index.has(module)) this.pick(module);
    return { t: this.t, selected: this.selected };
  }

  rolesAt() {
    return Object.fromEntries(this.scene.modules.map((m) => [m.id, this.scene.shownRoles.get(m.id) ?? null]));
  }

  // ---- module panel --------------------------------------------------------------------------
  pick(id) {
    const index = this.rec.index.get(id);
    if (index === undefined) return null;
    this.selected = id;
    const module = this.data.modules[index];
    const panel = this.ui.modulePanel;
    panel.replaceChildren(el("h3", "", `Module ${id}${id === this.data.meta.entry ? " (entry)" : ""}`));
    const facts = el("dl");
    const add = (name, value) => facts.append(el("dt", "", name), el("dd", "", value));
    add("lattice", `(${module.lattice.join(", ")}) ${module.axis}`);
    if (module.final_lattice && module.final_lattice.join() !== module.lattice.join()) {
      add("final cell", `(${module.final_lattice.join(", ")})`);
    } else if (module.final_lattice === null) {
      add("final cell", "taken away");
    }
    add("role now", roleAt(module, this.t) ?? "none");
    add("final role", module.final_role ?? "none");
    add("stored", module.fragments.length ? module.fragments.join(", ") : "nothing");
    add("errors", String(module.errors));
    this.stateBox = el("div", "rr-state-box");
    panel.append(facts, this.stateBox);
    this.#showState();
    panel.append(el("h3", "", "Role history"));
    const history = el("ol", "rr-history");
    if (!module.role_history.length) history.append(el("li", "", "no role was ever set"));
    for (const [t, role] of module.role_history) history.append(el("li", "", `${formatTime(t)} → ${role ?? "none"}`));
    panel.append(history);
    const own = [];
    this.data.events.forEach((e, i) => { if (e[1] === id) own.push(i); });
    panel.append(el("h3", "", `Events (${own.length})`));
    const list = el("ol", "rr-events rr-module-events");
    for (const i of own.slice(0, MODULE_EVENTS)) list.append(this.#eventRow(i));
    panel.append(list);
    if (own.length > MODULE_EVENTS) {
      panel.append(el("p", "rr-hint", `the first ${MODULE_EVENTS}; tick “only the selected module” below for all`));
    }
    this.#listEvents(true);
    return { id, lattice: module.lattice, roleHistory: module.role_history, fragments: module.fragments,
      text: panel.textContent };
  }

  // the selected module's state values at the current time, with their history
  #showState() {
    if (this.selected === null || !this.stateBox) return;
    const module = this.data.modules[this.rec.index.get(this.selected)];
    const section = stateSection(this.data, module, this.t, this.duration);
    this.stateBox.replaceChildren(...(section ? [section] : []));
  }

  stateAt(id, t) {
    const index = this.rec.index.get(id);
    return index === undefined ? null : stateAt(this.data, this.data.modules[index], t ?? this.t);
  }

  // ---- events and source lines ---------------------------------------------------------------
  #listEvents(force) {
    const only = this.ui.filterBox.checked ? this.selected : null;
    const now = lastAtOrBefore(this.eventTimes, this.t);
    const within = now >= this.listed.from && now < this.listed.to - 50;
    if (!force && this.listed.module === only && (within || this.listed.to >= this.data.events.length)) {
      this.#markPast(now);
      return;
    }
    const from = Math.max(0, now - 200);
    const list = this.ui.events;
    list.replaceChildren();
    let count = 0;
    let i = only === null ? from : 0;
    for (; i < this.data.events.length && count < EVENT_WINDOW; i++) {
      if (only !== null && this.data.events[i][1] !== only) continue;
      list.append(this.#eventRow(i));
      count++;
    }
    this.listed = { from: only === null ? from : 0, to: i, module: only };
    this.#markPast(now, true);
  }

  #eventRow(i) {
    const [t, module, kind, , , line, text] = this.data.events[i];
    const row = el("li");
    row.dataset.index = String(i);
    row.append(el("span", "rr-time", `${t.toFixed(2)} `), el("span", "rr-kind", kind),
      el("span", "", ` m${module} ${text}${line > 0 ? ` (line ${line})` : ""}`));
    if (i === this.selectedEvent) row.classList.add("rr-selected");
    return row;
  }

  #markPast(now, force = false) {
    if (!force && this.lastMarked === now) return;
    this.lastMarked = now;
    for (const row of this.ui.events.children) {
      const past = Number(row.dataset.index) <= now;
      row.classList.toggle("rr-past", past);
      row.classList.toggle("rr-future", !past);
    }
  }

  showEvent(index) {
    const event = this.data.events[index];
    if (!event) return null;
    const [t, module, kind, fragment, pc, line, text] = event;
    this.selectedEvent = index;
    for (const row of document.querySelectorAll(".rr-events .rr-selected")) row.classList.remove("rr-selected");
    for (const row of document.querySelectorAll(`.rr-events li[data-index="${index}"]`)) row.classList.add("rr-selected");
    const panel = this.ui.sourcePanel;
    const where = fragment >= 0 ? `fragment ${this.data.fragments[fragment]?.name ?? "?"}, pc ${pc}` : "no fragment";
    panel.replaceChildren(el("h3", "", `${kind} at ${formatTime(t)} on module ${module}`), el("p", "", text),
      el("p", "rr-hint", where));
    const lines = this.data.source.lines;
    let shown = null;
    if (line > 0 && line <= lines.length) {
      panel.append(el("p", "rr-line-ref", `${this.data.source.name}:${line}`));
      const pre = el("pre", "rr-code");
      for (let k = Math.max(1, line - 2); k <= Math.min(lines.length, line + 2); k++) {
        const span = el("span", k === line ? "rr-current" : "", `${String(k).padStart(4)}  ${lines[k - 1]}\n`);
        pre.append(span);
      }
      panel.append(pre);
      shown = { line, text: lines[line - 1] };
    } else {
      panel.append(el("p", "rr-hint", "this event has no source line"));
    }
    if (vscode) vscode.postMessage({ type: "revealLine", file: this.data.source.name, line, t, module, kind });
    this.seek(t);
    return shown;
  }

  // median and all frame times (update + render + GPU finish), ms, for benchmarks
  measureFrames(count = 120, from = 0, step = 0.05) {
    const gl = this.scene.renderer.getContext();
    const pixel = new Uint8Array(4);
    const times = [];
    const updates = [];
    for (let k = 0; k < count; k++) {
      const start = performance.now();
      this.scene.update(Math.min(this.duration, from + k * step));
      updates.push(performance.now() - start);
      this.scene.render();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel); // waits for the frame
      times.push(performance.now() - start);
    }
    const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];
    return { median: median(times), updateMedian: median(updates), times };
  }
}

function hook(replay) {
  return {
    ready: true,
    version: 1,
    duration: replay.duration,
    modules: replay.data.modules.map((m) => m.id),
    seek: (t) => { replay.seek(t); return replay.t; },
    time: () => replay.t,
    rolesAt: (t) => { if (t !== undefined) replay.seek(t); return replay.rolesAt(); },
    colourOf: (id) => replay.scene.colourOf(id),
    roleColour: (role) => (role === null ? NO_ROLE_COLOUR : replay.scene.roleColour.get(role) ?? NO_ROLE_COLOUR),
    pick: (id) => replay.pick(id),
    showMoment: (t, module) => replay.showMoment(t, module ?? null),
    // {name: value} of module `id` at time t (default: the time shown); null: a role state of a
    // role it does not play then; absent: unknown (its first changes were not recorded)
    stateAt: (id, t) => replay.stateAt(id, t),
    screenPoint: (id) => replay.scene.screenPoint(id),
    // a point of the canvas where module `id` is visible (not hidden by another), or null
    visiblePoint: (id) => {
      const c = replay.scene.screenPoint(id);
      for (let radius = 0; radius <= 40; radius += 4) {
        for (let a = 0; a < 8; a++) {
          const p = { x: c.x + radius * Math.cos((a * Math.PI) / 4), y: c.y + radius * Math.sin((a * Math.PI) / 4) };
          if (replay.scene.pickAt(p.x, p.y) === id) return p;
        }
      }
      return null;
    },
    events: () => replay.data.events.map(([t, module, kind, fragment, pc, line, text], index) => ({
      index, t, module, kind, fragment, pc, line, text })),
    showEvent: (index) => replay.showEvent(index),
    markers: () => replay.markers.map((m) => ({ ...m })),
    packetsShown: () => ({ ...replay.scene.shownPackets }),
    // structures that change: the modules in the world, a module's centre (m), the latches drawn
    presentAt: (t) => { if (t !== undefined) replay.seek(t); return replay.scene.modules.filter((m) => m.present).map((m) => m.id); },
    centreOf: (id) => { const m = replay.scene.modules[replay.rec.index.get(id)]; return m ? m.centre.toArray() : null; },
    latchesShown: () => replay.scene.shownLinks.map((k) => [...k]),
    setFollow: (on) => { replay.ui.followBox.checked = !!on; replay.scene.follow = !!on; replay.render(); },
    measureFrames: (count, from, step) => replay.measureFrames(count, from, step),
  };
}

async function main() {
  let ui;
  try {
    const data = readData();
    ui = buildLayout(data);
    const rec = await decode(data);
    const replay = new Replay(rec, ui);
    window.rdcdReplay = hook(replay);
    document.documentElement.dataset.replayReady = "true";
    if (vscode) {
      // the editor's debugger stopped: {type: "rdcd/seek", t, module} (vscode-extension/src/replayFollow.ts)
      window.addEventListener("message", (e) => {
        const m = e.data;
        if (m && m.type === "rdcd/seek" && typeof m.t === "number" && Number.isFinite(m.t)) replay.showMoment(m.t, m.module);
      });
      vscode.postMessage({ type: "ready" });
    }
  } catch (error) {
    const message = el("p", "rr-error", `The replay could not start: ${error && error.message ? error.message : error}`);
    document.body.prepend(message);
    window.rdcdReplay = { ready: false, error: String(error && error.message ? error.message : error) };
    document.documentElement.dataset.replayReady = "error";
    throw error;
  }
}

main();
