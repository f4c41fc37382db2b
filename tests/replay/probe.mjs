// Opens a replay page in headless Chromium (playwright-core) and prints, as JSON, what the tests
// of tests/replay/test_browser.py check: console errors, CSP violations, roles shown at given
// times, a real click on a module and on an event, and (optionally) frame times and a screenshot.
//   node probe.mjs PAGE.html '{"times":[...], "module": 3, "event": 12, "frames": 0, "shot": "x.png"}'
// With "messages": [...], the page runs as in a VS Code webview (an acquireVsCodeApi that records
// what the page posts) and gets each message as the extension would send it.
import { createRequire } from "node:module";
import * as path from "node:path";
import { pathToFileURL } from "node:url";

const [pagePath, optionsText = "{}"] = process.argv.slice(2);
const options = JSON.parse(optionsText);
const require = createRequire(path.resolve(process.env.RDCD_REPLAY_NODE_MODULES ?? ".", "x.js"));
const { chromium } = require("playwright-core");

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--ignore-gpu-blocklist", "--disable-background-networking", "--disable-component-update",
    "--no-first-run"],
});
const out = { console: [], pageErrors: [], csp: [], requests: [] };
try {
  const page = await browser.newPage({ viewport: { width: options.width ?? 1280, height: options.height ?? 800 } });
  page.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") out.console.push(`${m.type()}: ${m.text()}`); });
  page.on("pageerror", (e) => out.pageErrors.push(String(e.message ?? e)));
  page.on("request", (r) => { if (!r.url().startsWith("file:") && !r.url().startsWith("data:") && !r.url().startsWith("blob:")) out.requests.push(r.url()); });
  await page.addInitScript(() => {
    window.__csp = [];
    document.addEventListener("securitypolicyviolation", (e) => window.__csp.push(`${e.violatedDirective}: ${e.blockedURI}`));
  });
  if (options.messages) {
    await page.addInitScript(() => {
      window.__posted = [];
      window.acquireVsCodeApi = () => ({ postMessage: (m) => window.__posted.push(m) });
    });
  }
  await page.goto(pathToFileURL(path.resolve(pagePath)).href);
  await page.waitForFunction(() => document.documentElement.dataset.replayReady, null, { timeout: 30000 });
  out.ready = await page.evaluate(() => document.documentElement.dataset.replayReady);
  if (out.ready === "true") {
    out.duration = await page.evaluate(() => window.rdcdReplay.duration);
    out.roles = [];
    for (const t of options.times ?? []) {
      out.roles.push(await page.evaluate((t) => {
        const r = window.rdcdReplay;
        r.seek(t);
        const roles = r.rolesAt();
        const colours = Object.fromEntries(Object.keys(roles).map((id) => [id, r.colourOf(Number(id))]));
        const expected = Object.fromEntries(Object.entries(roles).map(([id, role]) => [id, r.roleColour(role)]));
        return { t: r.time(), roles, colours, expected, slider: Number(document.querySelector(".rr-slider").value) };
      }, t));
    }
    if (options.module !== undefined) {
      await page.evaluate((t) => window.rdcdReplay.seek(t), options.moduleTime ?? 0);
      const point = await page.evaluate((id) => window.rdcdReplay.visiblePoint(id), options.module);
      out.moduleVisible = point !== null;
      if (point) await page.mouse.click(point.x, point.y);
      out.modulePanel = await page.evaluate(() => document.querySelector(".rr-module").textContent);
    }
    if (options.stateTimes) {
      out.states = [];
      for (const t of options.stateTimes) {
        out.states.push(await page.evaluate(([t, id]) => {
          const r = window.rdcdReplay;
          r.seek(t);
          return { t: r.time(), values: r.stateAt(id), panel: document.querySelector(".rr-module .rr-state")?.textContent ?? null,
            sparklines: document.querySelectorAll(".rr-module .rr-spark-line").length };
        }, [t, options.module]));
      }
    }
    if (options.event !== undefined) {
      await page.evaluate(() => { window.rdcdReplay.seek(0); });
      const selector = `.rr-side > .rr-events li[data-index="${options.event}"]`;
      if (!(await page.$(selector))) await page.evaluate((i) => window.rdcdReplay.seek(window.rdcdReplay.events()[i].t), options.event);
      await page.click(selector);
      out.sourcePanel = await page.evaluate(() => document.querySelector(".rr-source").textContent);
      out.currentLine = await page.evaluate(() => document.querySelector(".rr-source .rr-current")?.textContent ?? null);
    }
    if (options.messages) {
      out.afterMessages = [];
      for (const message of options.messages) {
        out.afterMessages.push(await page.evaluate(async (m) => {
          window.postMessage(m, "*");
          await new Promise((resolve) => setTimeout(resolve, 50)); // the message event comes after this task
          const heading = document.querySelector(".rr-module h3");
          return { t: window.rdcdReplay.time(), slider: Number(document.querySelector(".rr-slider").value),
            module: heading ? heading.textContent : null };
        }, message));
      }
      out.posted = await page.evaluate(() => window.__posted);
    }
    if (options.structureTimes) {
      // structures that change: modules present, centres of the given modules, latches drawn
      out.structure = [];
      for (const t of options.structureTimes) {
        out.structure.push(await page.evaluate(([t, ids]) => {
          const r = window.rdcdReplay;
          const present = r.presentAt(t);
          return { t: r.time(), present, centres: Object.fromEntries(ids.map((id) => [id, r.centreOf(id)])),
            latches: r.latchesShown() };
        }, [t, options.structureIds ?? []]));
      }
    }
    if (options.markerEvent) {
      // a real click on the timeline where the first structure marker of that kind is
      const marker = await page.evaluate((kind) => window.rdcdReplay.markers().find((m) => m.event === kind) ?? null, options.markerEvent);
      out.marker = marker;
      if (marker) {
        const box = await page.evaluate(() => { const b = document.querySelector(".rr-markers").getBoundingClientRect(); return { x: b.left, y: b.top, w: b.width, h: b.height }; });
        const x = box.x + Math.round((marker.t / Math.max(out.duration, 1e-9)) * (box.w - 2)) + 2;
        await page.mouse.click(x, box.y + box.h - 2);
        out.sourcePanel = await page.evaluate(() => document.querySelector(".rr-source").textContent);
        out.currentLine = await page.evaluate(() => document.querySelector(".rr-source .rr-current")?.textContent ?? null);
      }
    }
    if (options.play) {
      await page.click(".rr-play");
      await page.waitForTimeout(options.play);
      out.playedTo = await page.evaluate(() => window.rdcdReplay.time());
      await page.click(".rr-play");
    }
    if (options.frames) {
      await page.evaluate(() => window.rdcdReplay.setFollow(true));
      out.frames = await page.evaluate((n) => window.rdcdReplay.measureFrames(n, 0, window.rdcdReplay.duration / n), options.frames);
    }
    out.markers = await page.evaluate(() => window.rdcdReplay.markers().length);
    out.text = await page.evaluate(() => document.body.innerText.slice(0, 20000));
    out.html = options.html ? await page.content() : undefined;
  } else {
    out.error = await page.evaluate(() => window.rdcdReplay && window.rdcdReplay.error);
  }
  if (options.shot) {
    if (options.follow) await page.evaluate(() => window.rdcdReplay.setFollow(true));
    await page.evaluate(() => { const side = document.querySelector(".rr-side"); if (side) side.scrollTop = 0; });
    await page.evaluate((t) => window.rdcdReplay && window.rdcdReplay.seek && window.rdcdReplay.seek(t), options.shotTime ?? 0);
    await page.screenshot({ path: options.shot });
  }
  out.csp = await page.evaluate(() => window.__csp);
} finally {
  await browser.close();
}
process.stdout.write(JSON.stringify(out));
