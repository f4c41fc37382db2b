import * as assert from "node:assert/strict";
import {
  escapeHtml,
  fragmentRows,
  moduleRows,
  renderErrorHtml,
  renderReportHtml,
  shorten,
  summaryEntries,
} from "../../src/reportHtml";

const report = {
  config: "car7",
  duration: 8,
  distance_m: 0.8312,
  summary: { modules: 7, collisions: 0 },
  modules: [
    { id: 0, name: "driver", role: null, position: [0, 0, 0] },
    { id: 1, final_role: "Axle", lattice: [0, 1, -1], role_history: [[0, null], [0.5, "Axle"]], errors: [] },
    { id: 3, role: "RightWheel" },
  ],
  fragments: [
    { role: "Wheel", method: "move", kind: "startup", size: 31 },
    { role: "Axle", method: "steer", kind: "behavior", bytes: 40 },
  ],
  trajectory: [[0, 0], [0, 1]],
};

describe("renderReportHtml", () => {
  const html = renderReportHtml({
    report,
    plotSrc: "https://file+.vscode-resource.vscode-cdn.net/tmp/plot.png?t=1",
    cspSource: "https://*.vscode-cdn.net",
    fileName: "obstacle_avoidance.rdcd",
    options: { config: "car7", duration: 8 },
  });

  it("has a restrictive CSP without scripts", () => {
    assert.match(html, /Content-Security-Policy" content="default-src 'none'; img-src https:\/\/\*\.vscode-cdn\.net data:;/);
    assert.doesNotMatch(html, /<script/);
  });

  it("shows the summary, roles per module, fragment sizes and the plot", () => {
    assert.match(html, /<h2>Summary<\/h2>/);
    assert.match(html, /<td>Distance m<\/td><td>0\.831<\/td>/);
    assert.match(html, /<td>Collisions<\/td><td>0<\/td>/);
    assert.match(html, /<td>driver<\/td><td>\(none\)<\/td>/);
    assert.match(html, /<td>1<\/td><td>Axle<\/td><td>lattice: 0, 1, -1; role_history: 2 entries<\/td>/);
    assert.match(html, /<td>Wheel · move · startup<\/td><td>31<\/td>/);
    assert.match(html, /<td>Axle · steer · behavior<\/td><td>40<\/td>/);
    assert.match(html, /<img id="trajectory" src="https:\/\/file\+\.vscode-resource\.vscode-cdn\.net\/tmp\/plot\.png\?t=1"/);
    assert.match(html, /obstacle_avoidance\.rdcd/);
  });

  it("says so when there is no plot", () => {
    const bare = renderReportHtml({ report: {}, cspSource: "x", fileName: "a.rdcd" });
    assert.match(bare, /produced no plot/);
    assert.match(bare, /lists no modules/);
    assert.match(bare, /lists no fragments/);
  });

  it("escapes everything that comes from the report", () => {
    const evil = renderReportHtml({ report: { note: "<img src=x onerror=alert(1)>" }, cspSource: "x", fileName: "<b>.rdcd" });
    assert.doesNotMatch(evil, /<img src=x/);
    assert.match(evil, /&lt;img src=x onerror=alert\(1\)&gt;/);
    assert.match(evil, /&lt;b&gt;\.rdcd/);
  });
});

describe("report readers", () => {
  it("reads modules given as a map from module to role", () => {
    assert.deepEqual(moduleRows({ roles_per_module: { m0: "Axle", m1: null } }), [
      { module: "m0", role: "Axle", details: "" },
      { module: "m1", role: "(none)", details: "" },
    ]);
  });

  it("reads fragments given as a map from name to size", () => {
    assert.deepEqual(fragmentRows({ fragment_sizes: { "Wheel.move": 31 } }), [{ fragment: "Wheel.move", size: "31", details: "" }]);
    assert.deepEqual(fragmentRows({ compile: { fragments: [{ name: "f", size: 3, packet: 10 }] } }), [
      { fragment: "f", size: "3", details: "packet: 10" },
    ]);
  });

  it("puts scalar fields and small records into the summary and skips the plot path", () => {
    assert.deepEqual(
      summaryEntries({ steps: 10, ok: true, plotPath: "/p.png", messages: { sent: 3, dropped: 0 }, big: { a: [1] } }),
      [
        ["Steps", "10"],
        ["Ok", "yes"],
        ["Messages", "sent 3, dropped 0"],
      ],
    );
  });

  it("shortens long lists in the raw report", () => {
    assert.deepEqual(shorten({ t: [1, 2, 3, 4] }, 2), { t: [1, 2, "… 2 more"] });
  });

  it("escapes HTML", () => {
    assert.equal(escapeHtml(`<a href="x">'&'</a>`), "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;");
    assert.match(renderErrorHtml("a.rdcd", "boom <x>", "src"), /boom &lt;x&gt;/);
  });
});
