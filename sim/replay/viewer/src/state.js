// A module's state values over time, for its panel: the value of each state at the current time, a
// sparkline of its whole history with the current time marked, and the last changes up to now.
// data.states: [{name, initial, owner, roles}], module.state_history: [[t, name, value], ...]
// (sim/state_report.py). A module's state memory starts at 0; a role state is shown only while the
// module plays one of the roles that have it.
import { roleAt } from "./data.js";
import { el, formatTime } from "./ui.js";

const SVG = "http://www.w3.org/2000/svg";
const RECENT = 12; // changes listed (the last ones at or before the current time)
const WIDTH = 120;
const HEIGHT = 22;

function names(data) {
  return [...new Set((data.states ?? []).map((s) => s.name))];
}

// {name: value | null} of `module` at time t; null: a role state of a role it does not play then
export function stateAt(data, module, t) {
  const role = roleAt(module, t);
  const out = {};
  for (const state of data.states ?? []) {
    if (state.name in out && out[state.name] !== null) continue;
    const has = state.owner === null || (state.roles ?? [state.owner]).includes(role);
    // before its first recorded change a value is 0 (memory starts so), unless changes were left out
    out[state.name] = has ? (module.state_history_omitted ? undefined : 0) : null;
  }
  const history = module.state_history ?? [];
  const last = {};
  for (const [time, name, value] of history) {
    if (time > t + 1e-9) break;
    last[name] = value;
  }
  for (const [name, value] of Object.entries(last)) if (out[name] !== null) out[name] = value;
  return out;
}

function sparkline(history, name, duration, t) {
  const svg = document.createElementNS(SVG, "svg");
  svg.setAttribute("class", "rr-spark");
  svg.setAttribute("width", String(WIDTH));
  svg.setAttribute("height", String(HEIGHT));
  svg.setAttribute("viewBox", `0 0 ${WIDTH} ${HEIGHT}`);
  const changes = history.filter((c) => c[1] === name);
  const x = (time) => (Math.min(duration, Math.max(0, time)) / Math.max(duration, 1e-9)) * (WIDTH - 2) + 1;
  if (changes.length) {
    const values = [0, ...changes.map((c) => c[2])];
    const low = Math.min(...values);
    const high = Math.max(...values);
    const y = (v) => (high === low ? HEIGHT / 2 : HEIGHT - 2 - ((v - low) / (high - low)) * (HEIGHT - 4));
    let value = 0;
    const points = [[x(0), y(0)]];
    for (const [time, , v] of changes) {
      points.push([x(time), y(value)], [x(time), y(v)]);
      value = v;
    }
    points.push([x(duration), y(value)]);
    const line = document.createElementNS(SVG, "polyline");
    line.setAttribute("points", points.map(([a, b]) => `${a.toFixed(1)},${b.toFixed(1)}`).join(" "));
    line.setAttribute("class", "rr-spark-line");
    svg.append(line);
  }
  const now = document.createElementNS(SVG, "line");
  for (const [k, v] of [["x1", x(t)], ["x2", x(t)], ["y1", 0], ["y2", HEIGHT]]) now.setAttribute(k, v.toFixed(1));
  now.setAttribute("class", "rr-spark-now");
  svg.append(now);
  return svg;
}

// the panel section: values now, sparklines, recent changes; null when the program has no state
export function stateSection(data, module, t, duration) {
  const all = names(data);
  if (!all.length) return null;
  const section = el("div", "rr-state");
  section.append(el("h3", "", `State at ${formatTime(t)}`));
  const values = stateAt(data, module, t);
  const table = el("table", "rr-state-values");
  const roles = new Map((data.states ?? []).map((s) => [s.name, s.roles ?? []]));
  const history = module.state_history ?? [];
  for (const name of all) {
    const row = el("tr");
    const value = values[name];
    const shown = value === null ? `— (only in ${roles.get(name).join(", ")})` : value === undefined ? "?" : String(value);
    row.dataset.state = name;
    const cell = el("td", "rr-state-spark");
    cell.append(sparkline(history, name, duration, t));
    row.append(el("td", "rr-state-name", name), el("td", "rr-state-value", shown), cell);
    table.append(row);
  }
  section.append(table);
  const past = history.filter((c) => c[0] <= t + 1e-9);
  const omitted = module.state_history_omitted ?? 0;
  section.append(el("h3", "", `State changes (${past.length} up to now)`));
  if (omitted) section.append(el("p", "rr-hint", `the first ${omitted} changes of the run are not recorded`));
  const list = el("ol", "rr-history rr-state-changes");
  if (!past.length) list.append(el("li", "", "no change yet"));
  for (const [time, name, value] of past.slice(-RECENT)) list.append(el("li", "", `${formatTime(time)} ${name} = ${value}`));
  section.append(list);
  return section;
}
