import * as assert from "node:assert/strict";
import { createHash } from "node:crypto";
import {
  embeddedPolicy,
  formatPolicy,
  parsePolicy,
  policyProblem,
  renderReplayHtml,
  ReplayPageError,
  revealedLine,
} from "../../src/replayHtml";
import type { SimulationReport } from "../../src/simulateArgs";

const sha256 = (text: string) => `'sha256-${createHash("sha256").update(text, "utf8").digest("base64")}'`;
const escapeAttribute = (text: string) => text.replace(/&/g, "&amp;").replace(/"/g, "&quot;").replace(/'/g, "&#x27;");

const SCRIPT = 'window.rdcdReplay = { ready: true }; document.body.append(document.createElement("div"));';
const STYLE = "html, body { margin: 0; height: 100%; } .rr-root { height: 100vh; }";

/** A page as sim/replay/page.py's render_page writes it (its policy escaped by html.escape). */
function replayPage(policy?: string): string {
  const csp =
    policy ??
    `default-src 'none'; script-src ${sha256(SCRIPT)}; style-src ${sha256(STYLE)}; img-src data: blob:; connect-src 'none'; base-uri 'none'; form-action 'none'`;
  return (
    '<!doctype html>\n<html lang="en"><head><meta charset="utf-8">\n' +
    `<meta http-equiv="Content-Security-Policy" content="${escapeAttribute(csp)}">\n` +
    '<meta name="viewport" content="width=device-width, initial-scale=1">\n' +
    `<title>rdcd replay: a.rdcd on car7</title>\n<style>${STYLE}</style>\n</head><body>\n` +
    "<noscript>The replay needs JavaScript and WebGL.</noscript>\n" +
    '<script type="application/json" id="rdcd-replay-data">{"meta":{"program":"a.rdcd"}}</script>\n' +
    `<script>${SCRIPT}</script>\n</body></html>\n`
  );
}

const report: SimulationReport = {
  config: "car7",
  collided: false,
  modules: [{ id: 1, final_role: "Axle", role_history: [[0.2, "Axle"]] }],
  fragments: [{ name: "Axle_entry", size: 40 }],
};

const NONCE = "c2VjcmV0LW5vbmNlLTEyMzQ1Ng==";
const CSP_SOURCE = "https://*.vscode-cdn.net";

function render(page = replayPage(), extra: Partial<Parameters<typeof renderReplayHtml>[0]> = {}): string {
  return renderReplayHtml({
    page,
    report,
    plotSrc: "https://file+.vscode-resource.vscode-cdn.net/store/plot.png?t=1",
    cspSource: CSP_SOURCE,
    fileName: "obstacle_avoidance.rdcd",
    nonce: NONCE,
    ...extra,
  });
}

function policyOf(html: string): Map<string, string[]> {
  const metas = [...html.matchAll(/<meta http-equiv="Content-Security-Policy" content="([^"]*)">/g)];
  assert.equal(metas.length, 1, "exactly one policy");
  return parsePolicy((metas[0]?.[1] ?? "").replace(/&#39;|&#x27;/g, "'").replace(/&quot;/g, '"').replace(/&amp;/g, "&"));
}

describe("renderReplayHtml", () => {
  const html = render();

  it("keeps the page's policy: its script by hash, nothing remote, and adds only the nonce'd style and the plot's source", () => {
    const policy = policyOf(html);
    assert.deepEqual(policy.get("default-src"), ["'none'"]);
    assert.deepEqual(policy.get("script-src"), [sha256(SCRIPT)]);
    assert.deepEqual(policy.get("style-src"), [sha256(STYLE), `'nonce-${NONCE}'`]);
    assert.deepEqual(policy.get("img-src"), ["data:", "blob:", CSP_SOURCE]);
    assert.deepEqual(policy.get("connect-src"), ["'none'"]);
    assert.equal(policyProblem(new Map([...policy].map(([name, sources]) => [name, sources.filter((s) => s !== CSP_SOURCE)]))), undefined);
  });

  it("leaves the page's script and style untouched, so their hashes still match", () => {
    assert.ok(html.includes(`<script>${SCRIPT}</script>`));
    assert.ok(html.includes(`<style>${STYLE}</style>`));
    assert.ok(html.includes('<script type="application/json" id="rdcd-replay-data">{"meta":{"program":"a.rdcd"}}</script>'));
    assert.equal((html.match(/<script/g) ?? []).length, 2, "no script of ours");
  });

  it("adds the tabs and the report before the replay's own body, and its style with the nonce in the head", () => {
    const head = html.slice(0, html.indexOf("</head>"));
    assert.match(head, new RegExp(`<style nonce="${NONCE.replace(/[+/=]/g, "\\$&")}">`));
    const body = html.slice(html.indexOf("<body>"));
    assert.ok(body.indexOf('id="rdcd-tabs"') < body.indexOf("<noscript>"));
    assert.match(body, /<input type="radio" name="rdcd-tab" id="rdcd-tab-replay" checked>/);
    assert.match(body, /<input type="radio" name="rdcd-tab" id="rdcd-tab-report">/);
    assert.match(body, /<div id="rdcd-report"><h1>RDCD simulation: obstacle_avoidance\.rdcd<\/h1>/);
    assert.match(body, /<img id="trajectory" src="https:\/\/file\+\.vscode-resource\.vscode-cdn\.net\/store\/plot\.png\?t=1"/);
    assert.match(body, /<td>1<\/td><td>Axle<\/td>/);
    assert.match(body, /<td>Axle_entry<\/td><td>40<\/td>/);
    assert.match(head, /body:has\(#rdcd-tab-report:checked\) #rdcd-report \{ display: block; \}/);
    assert.match(head, /#rdcd-report table/, "the report's rules are scoped to it");
    assert.doesNotMatch(head, /\n(body \{ font-family|h1 \{|h2 \{|table \{|pre \{|th, td \{)/, "no rule of the report reaches the replay");
  });

  it("escapes the file name and the report", () => {
    const evil = render(replayPage(), { fileName: "<img src=x onerror=alert(1)>.rdcd", report: { ...report, note: "</div><script>alert(1)</script>" } });
    assert.doesNotMatch(evil, /<img src=x/);
    assert.doesNotMatch(evil, /<script>alert/);
    assert.equal((evil.match(/<script/g) ?? []).length, 2);
  });

  it("says the page produced no plot when there is none", () => {
    assert.match(render(replayPage(), { plotSrc: undefined }), /The simulation produced no plot/);
  });

  it("refuses a page without a policy, with a remote or unsafe source, or with two policies", () => {
    const noPolicy = replayPage().replace(/<meta http-equiv="Content-Security-Policy"[^>]*>\n/, "");
    assert.throws(() => render(noPolicy), (error: unknown) => error instanceof ReplayPageError && /no Content-Security-Policy/.test(error.message));
    for (const [policy, expected] of [
      [`default-src 'none'; script-src https://cdn.example.com ${sha256(SCRIPT)}`, /allows https:\/\/cdn\.example\.com in script-src/],
      [`default-src 'none'; script-src 'unsafe-inline'`, /allows 'unsafe-inline' in script-src/],
      [`default-src 'none'; script-src 'unsafe-eval' ${sha256(SCRIPT)}`, /allows 'unsafe-eval'/],
      [`default-src 'none'; connect-src *`, /allows \* in connect-src/],
      [`default-src 'none'; img-src http:`, /allows http: in img-src/],
      [`default-src 'self'; script-src ${sha256(SCRIPT)}`, /default-src 'none'/],
      [`script-src ${sha256(SCRIPT)}`, /default-src 'none'/],
    ] as const) {
      assert.throws(() => render(replayPage(policy)), (error: unknown) => error instanceof ReplayPageError && expected.test(error.message), policy);
    }
    const twice = replayPage().replace("<title>", `<meta http-equiv="Content-Security-Policy" content="default-src *">\n<title>`);
    assert.throws(() => render(twice), /more than one/);
  });

  it("refuses a weak nonce", () => {
    assert.throws(() => render(replayPage(), { nonce: "abc" }), ReplayPageError);
    assert.throws(() => render(replayPage(), { nonce: '"><script>alert(1)</script>' }), ReplayPageError);
  });
});

describe("policies", () => {
  it("parse and format round-trip, the first of a repeated directive counting", () => {
    const policy = parsePolicy("default-src 'none';  script-src 'sha256-AAA=' ; img-src data:; script-src *");
    assert.deepEqual([...policy.keys()], ["default-src", "script-src", "img-src"]);
    assert.equal(formatPolicy(policy), "default-src 'none'; script-src 'sha256-AAA='; img-src data:");
  });

  it("adding a source replaces 'none' and creates a missing directive", () => {
    const policy = embeddedPolicy(parsePolicy("default-src 'none'; img-src 'none'"), NONCE, "'self' https://x.example");
    assert.deepEqual(policy.get("img-src"), ["'self'", "https://x.example"]);
    assert.deepEqual(policy.get("style-src"), [`'nonce-${NONCE}'`]);
  });
});

describe("revealedLine", () => {
  it("gives the zero-based line of a revealLine message within the document", () => {
    assert.equal(revealedLine({ type: "revealLine", file: "a.rdcd", line: 12, t: 1.5, module: 3, kind: "handler" }, 40), 11);
    assert.equal(revealedLine({ type: "revealLine", line: 1 }, 1), 0);
    assert.equal(revealedLine({ type: "revealLine", line: 40 }, 40), 39);
  });

  it("ignores other messages, events without a line and lines the document does not have", () => {
    for (const message of [
      { type: "ready" },
      { type: "revealLine", line: 0 },
      { type: "revealLine", line: -3 },
      { type: "revealLine", line: 41 },
      { type: "revealLine", line: 2.5 },
      { type: "revealLine", line: "7" },
      { type: "revealLine" },
      null,
      "revealLine",
      [1],
    ]) {
      assert.equal(revealedLine(message, 40), undefined, JSON.stringify(message));
    }
  });
});
