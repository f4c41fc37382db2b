// Opens every page of the built documentation site in headless Chromium (playwright-core), searches
// it and looks at the colours of one page's first RDCD block, printing JSON for
// tests/docs/test_site_browser.py:
//   node site_probe.mjs BASE_URL '["index.html", "language/index.html", ...]' QUERY [HIGHLIGHT_PAGE]
// {"pages": {path: {"status", "title", "errors": [...]}}, "search": {"meta", "results": [...]},
//  "highlight": {"blocks", "plain", "spans": [{"text", "cls", "color"}, ...]} or null}
// A request to anything but BASE_URL is an error: the site must be readable offline.
import { createRequire } from "node:module";
import * as path from "node:path";

const [base, pagesText, query, highlightPage] = process.argv.slice(2);
const require = createRequire(path.resolve(process.env.RDCD_NODE_MODULES ?? ".", "x.js"));
const { chromium } = require("playwright-core");

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
const out = { pages: {}, search: null, highlight: null };
try {
  const page = await browser.newPage();
  let errors = [];
  page.on("console", (m) => { if (m.type() === "error") errors.push(`console: ${m.text()}`); });
  page.on("pageerror", (e) => errors.push(`page: ${e.message ?? e}`));
  // ERR_ABORTED: a request the next navigation cut short (the search worker's index, late), not a fault
  page.on("requestfailed", (r) => {
    const why = r.failure()?.errorText ?? "";
    if (!why.includes("ERR_ABORTED")) errors.push(`request failed: ${r.url()} ${why}`);
  });
  page.on("response", (r) => { if (r.status() >= 400) errors.push(`HTTP ${r.status()}: ${r.url()}`); });
  page.on("request", (r) => {
    const url = r.url();
    if (!url.startsWith(base) && !url.startsWith("data:") && !url.startsWith("blob:")) {
      errors.push(`external request: ${url}`);
    }
  });
  for (const p of JSON.parse(pagesText)) {
    errors = [];
    // networkidle: the search worker and every late script have loaded (or failed) before the next page
    const response = await page.goto(base + p, { waitUntil: "networkidle" });
    out.pages[p] = { status: response?.status() ?? 0, title: await page.title(), errors };
  }
  errors = [];
  await page.goto(base + "index.html", { waitUntil: "load" });
  await page.keyboard.press("/");  // Material's shortcut: focus the search field
  await page.keyboard.type(query, { delay: 20 });
  await page.waitForSelector(".md-search-result__item", { timeout: 30000 });
  out.search = {
    meta: await page.locator(".md-search-result__meta").innerText(),
    results: await page.locator(".md-search-result__item a").evaluateAll((as) => as.map((a) => a.getAttribute("href"))),
    errors,
  };
  if (highlightPage) {
    await page.goto(base + highlightPage, { waitUntil: "load" });
    // the colour each span of the first RDCD block is drawn in, and that of the block's plain text
    out.highlight = await page.evaluate(() => {
      const blocks = document.querySelectorAll(".language-rdcd code");
      if (blocks.length === 0) return { blocks: 0, plain: null, spans: [] };
      const code = blocks[0];
      return {
        blocks: blocks.length,
        plain: getComputedStyle(code).color,
        spans: [...code.querySelectorAll("span[class]")].map((s) => ({
          text: s.textContent, cls: s.className, color: getComputedStyle(s).color })),
      };
    });
  }
} finally {
  await browser.close();
}
console.log(JSON.stringify(out));
