import * as assert from "node:assert/strict";
import { escapeHtml, moduleRows, renderErrorHtml, renderReportHtml, shorten, summaryEntries } from "../../src/reportHtml";
import type { SimulationReport } from "../../src/simulateArgs";

// The shape of sim/report.py's report, cut down.
const report: SimulationReport = {
  world: "physics",
  config: "car7",
  duration_s: 8,
  min_obstacle_distance_m: 0.8312,
  collided: false,
  messages: { sent: 32, delivered: 30, dropped: 2 },
  modules: [
    { id: 0, lattice: [0, 0, 0], orientation: "NS", final_role: null, role_history: [], errors: [] },
    { id: 1, lattice: [0, 1, -1], orientation: "UD", final_role: "Axle", role_history: [[0.2, "Wheel"], [0.5, "Axle"]], errors: [] },
    { id: 3, lattice: [1, 1, 0], orientation: "EW", final_role: "RightWheel", role_history: [], errors: [{ t: 1, message: "m" }] },
  ],
  fragments: [
    { name: "discover_RightWheel_LeftWheel", size: 41 },
    { name: "Axle_entry", size: 40 },
  ],
  trajectory: [[0, 0, 0, 0], [0.1, 0, 1, 0]],
};

describe("renderReportHtml", () => {
  const html = renderReportHtml({
    report,
    plotSrc: "https://file+.vscode-resource.vscode-cdn.net/tmp/plot.png?t=1",
    cspSource: "https://*.vscode-cdn.net",
    fileName: "obstacle_avoidance.rdcd",
  });

  it("has a restrictive CSP without scripts", () => {
    assert.match(html, /Content-Security-Policy" content="default-src 'none'; img-src https:\/\/\*\.vscode-cdn\.net data:;/);
    assert.doesNotMatch(html, /<script/);
  });

  it("shows the summary, roles per module, fragment sizes and the plot", () => {
    assert.match(html, /<h2>Summary<\/h2>/);
    assert.match(html, /<td>Min obstacle distance m<\/td><td>0\.831<\/td>/);
    assert.match(html, /<td>Collided<\/td><td>no<\/td>/);
    assert.match(html, /<td>Messages<\/td><td>sent 32, delivered 30, dropped 2<\/td>/);
    assert.match(html, /<td>0<\/td><td>\(none\)<\/td><td>lattice: 0, 0, 0; orientation: NS<\/td>/);
    assert.match(html, /<td>1<\/td><td>Axle<\/td><td>lattice: 0, 1, -1; orientation: UD; role_history: 2 entries<\/td>/);
    assert.match(html, /<td>discover_RightWheel_LeftWheel<\/td><td>41<\/td>/);
    assert.match(html, /<td>Axle_entry<\/td><td>40<\/td>/);
    assert.match(html, /<img id="trajectory" src="https:\/\/file\+\.vscode-resource\.vscode-cdn\.net\/tmp\/plot\.png\?t=1"/);
    assert.match(html, /obstacle_avoidance\.rdcd/);
  });

  it("says so when there is no plot, no module and no fragment", () => {
    const bare = renderReportHtml({ report: { modules: [], fragments: [] }, cspSource: "x", fileName: "a.rdcd" });
    assert.match(bare, /produced no plot/);
    assert.match(bare, /lists no modules/);
    assert.match(bare, /lists no fragments/);
  });

  it("escapes everything that comes from the report", () => {
    const evil = renderReportHtml({
      report: { note: "<img src=x onerror=alert(1)>", modules: [], fragments: [{ name: "<b>", size: 1 }] },
      cspSource: "x",
      fileName: "<b>.rdcd",
    });
    assert.doesNotMatch(evil, /<img src=x/);
    assert.doesNotMatch(evil, /<td><b><\/td>/);
    assert.match(evil, /&lt;img src=x onerror=alert\(1\)&gt;/);
    assert.match(evil, /&lt;b&gt;\.rdcd/);
  });
});

describe("report readers", () => {
  it("reads each module's id, final role and the rest of what the report says of it", () => {
    assert.deepEqual(moduleRows(report), [
      { module: "0", role: "(none)", details: "lattice: 0, 0, 0; orientation: NS" },
      { module: "1", role: "Axle", details: "lattice: 0, 1, -1; orientation: UD; role_history: 2 entries" },
      { module: "3", role: "RightWheel", details: "lattice: 1, 1, 0; orientation: EW; errors: 1 entry" },
    ]);
  });

  it("puts scalar fields and small records of scalars into the summary", () => {
    assert.deepEqual(summaryEntries({ ...report, events: [{ t: 0, kind: "role" }], module_start_xy: { "0": [0, 1] } }), [
      ["World", "physics"],
      ["Config", "car7"],
      ["Duration s", "8"],
      ["Min obstacle distance m", "0.831"],
      ["Collided", "no"],
      ["Messages", "sent 32, delivered 30, dropped 2"],
    ]);
  });

  it("shortens long lists in the raw report", () => {
    assert.deepEqual(shorten({ t: [1, 2, 3, 4] }, 2), { t: [1, 2, "… 2 more"] });
  });

  it("escapes HTML", () => {
    assert.equal(escapeHtml(`<a href="x">'&'</a>`), "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;");
    assert.match(renderErrorHtml("a.rdcd", "boom <x>", "src"), /boom &lt;x&gt;/);
  });
});
