// The page around the scene: header, timeline with markers, module panel, event list, source
// line. Every text from the recording goes through textContent (never markup).
import { MARKER_COLOURS } from "./markers.js";

export function el(tag, className, text) {
  const node = document.createElement(tag);
  if (className) node.className = className;
  if (text !== undefined) node.textContent = text;
  return node;
}

export function formatTime(t) {
  return `${t.toFixed(2)} s`;
}

export function buildLayout(data) {
  const root = el("div", "rr-root");
  const header = el("header", "rr-header");
  const meta = data.meta;
  header.append(el("span", "rr-title", `${meta.program} · ${meta.config} · ${meta.world} world`),
    el("span", "rr-sub", `obstacle ${meta.obstacle} · seed ${meta.seed} · loss ${meta.packet_loss}`));
  for (const note of meta.notes) header.append(el("span", "rr-note", `note: ${note}`));
  const view = el("div", "rr-view");
  const side = el("aside", "rr-side");
  const legend = el("div", "rr-legend");
  const modulePanel = el("section", "rr-module");
  modulePanel.append(el("p", "rr-hint", "Click a module to see its id, lattice position, state values, role history, events and stored fragments."));
  const sourcePanel = el("section", "rr-source");
  sourcePanel.append(el("p", "rr-hint", "Click an event to see its source line."));
  const eventsHeader = el("div", "rr-events-head");
  const eventFilter = el("label", "rr-filter");
  const filterBox = el("input");
  filterBox.type = "checkbox";
  eventFilter.append(filterBox, el("span", "", " only the selected module"));
  eventsHeader.append(el("h3", "", "Events"), eventFilter);
  const events = el("ol", "rr-events");
  side.append(legend, modulePanel, sourcePanel, eventsHeader, events);
  const timeline = el("footer", "rr-timeline");
  const play = el("button", "rr-play", "▶");
  play.type = "button";
  play.title = "play / pause (space)";
  const speed = el("select", "rr-speed");
  for (const s of [0.25, 0.5, 1, 2, 4, 8, 16]) {
    const option = el("option", "", `${s}×`);
    option.value = String(s);
    if (s === 1) option.selected = true;
    speed.append(option);
  }
  const follow = el("label", "rr-follow");
  const followBox = el("input");
  followBox.type = "checkbox";
  follow.append(followBox, el("span", "", " follow"));
  const track = el("div", "rr-track");
  const markers = el("canvas", "rr-markers");
  const slider = el("input", "rr-slider");
  slider.type = "range";
  slider.min = "0";
  slider.max = String(meta.duration_s);
  slider.step = "0.01";
  slider.value = "0";
  track.append(markers, slider);
  const clock = el("span", "rr-clock", formatTime(0));
  timeline.append(play, speed, follow, track, clock);
  const markerLegend = el("div", "rr-marker-legend");
  for (const [kind, colour] of Object.entries(MARKER_COLOURS)) {
    const item = el("span", "rr-key", kind);
    const swatch = el("i", "rr-swatch");
    swatch.style.background = colour;
    item.prepend(swatch);
    markerLegend.append(item);
  }
  timeline.append(markerLegend);
  root.append(header, view, side, timeline);
  document.body.append(root);
  return { root, view, side, legend, modulePanel, sourcePanel, events, filterBox, play, speed, followBox,
    markers, slider, clock };
}

export function fillLegend(legend, roleColour, noRoleColour) {
  legend.replaceChildren(el("h3", "", "Roles"));
  const list = el("div", "rr-role-keys");
  for (const [name, colour] of [...roleColour, ["no role", noRoleColour]]) {
    const item = el("span", "rr-key", name);
    const swatch = el("i", "rr-swatch");
    swatch.style.background = colour;
    item.prepend(swatch);
    list.append(item);
  }
  legend.append(list);
}

export function drawMarkers(canvas, markers, duration) {
  const width = canvas.clientWidth || 600;
  const height = canvas.clientHeight || 14;
  canvas.width = width;
  canvas.height = height;
  const g = canvas.getContext("2d");
  g.clearRect(0, 0, width, height);
  const rows = { detection: 0, role: 1, reversal: 2, error: 3, lost: 4, structure: 5 };
  const rowHeight = height / 6;
  for (const marker of markers) {
    const x = Math.round((marker.t / Math.max(duration, 1e-9)) * (width - 2)) + 1;
    g.fillStyle = MARKER_COLOURS[marker.kind];
    g.fillRect(x, rows[marker.kind] * rowHeight, 2, rowHeight);
  }
}
