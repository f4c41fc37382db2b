// End-to-end test of the extension in a real VS Code: code-server (VS Code for the web) driven by
// headless Chromium through playwright-core. Installs both with tools/code-server-setup.sh into
// $RDCD_E2E_DIR (default ~/.cache/rdcd-e2e), packages and installs the vsix, opens a copy of
// the examples and checks each feature through the UI. Screenshots go to test-artifacts/.
//
//   node test/e2e/run.mjs [--no-package] [--docs-screenshot]
//
// Environment: RDCD_E2E_DIR, RDCD_E2E_PYTHON (interpreter with the rdcd package, used when
// rdcd-lsp is not on PATH), CHROMIUM (default /usr/bin/chromium), RDCD_E2E_HEADED=1.
import { execFileSync, spawn, spawnSync } from "node:child_process";
import * as fs from "node:fs";
import * as http from "node:http";
import { createRequire } from "node:module";
import * as net from "node:net";
import * as os from "node:os";
import * as path from "node:path";
import { fileURLToPath } from "node:url";

const extensionDir = path.resolve(path.dirname(fileURLToPath(import.meta.url)), "..", "..");
const repoDir = path.resolve(extensionDir, "..");
// Outside the checkout, so that fresh clones (CI) reuse it.
const cacheHome = process.env.XDG_CACHE_HOME ?? path.join(os.homedir(), ".cache");
const e2eDir = path.resolve(process.env.RDCD_E2E_DIR ?? path.join(cacheHome, "rdcd-e2e"));
const artifacts = path.join(extensionDir, "test-artifacts");
const vsix = path.join(extensionDir, "rdcd-0.1.0.vsix");
const TOTAL_BUDGET_MS = 9 * 60 * 1000;
const started = Date.now();

const results = [];
let shotCount = 0;

function log(message) {
  const seconds = ((Date.now() - started) / 1000).toFixed(1).padStart(6);
  console.log(`[e2e ${seconds}s] ${message}`);
}

function sleep(ms) {
  return new Promise((resolve) => setTimeout(resolve, ms));
}

/** Retries `action` (a UI wait or interaction) a few times before giving up. */
async function retry(what, action, { attempts = 3, pause = 1500 } = {}) {
  let lastError;
  for (let attempt = 1; attempt <= attempts; attempt++) {
    try {
      return await action(attempt);
    } catch (error) {
      lastError = error;
      log(`  ${what}: attempt ${attempt} failed: ${String(error.message ?? error).split("\n")[0]}`);
      await sleep(pause);
    }
  }
  throw lastError;
}

async function until(what, condition, { timeout = 15000, interval = 250 } = {}) {
  const deadline = Date.now() + timeout;
  let last;
  while (Date.now() < deadline) {
    last = await condition();
    if (last) {
      return last;
    }
    await sleep(interval);
  }
  throw new Error(`timed out after ${timeout} ms waiting for ${what}`);
}

function findOnPath(name) {
  for (const dir of (process.env.PATH ?? "").split(path.delimiter)) {
    const candidate = path.join(dir, name);
    try {
      fs.accessSync(candidate, fs.constants.X_OK);
      if (fs.statSync(candidate).isFile()) {
        return candidate;
      }
    } catch {
      // not here
    }
  }
  return undefined;
}

function freePort() {
  return new Promise((resolve, reject) => {
    const server = net.createServer();
    server.unref();
    server.on("error", reject);
    server.listen(0, "127.0.0.1", () => {
      const { port } = server.address();
      server.close(() => resolve(port));
    });
  });
}

function httpStatus(url) {
  return new Promise((resolve) => {
    const request = http.get(url, (response) => {
      response.resume();
      resolve(response.statusCode);
    });
    request.on("error", () => resolve(0));
    request.setTimeout(2000, () => {
      request.destroy();
      resolve(0);
    });
  });
}

function setup() {
  log(`installing code-server, Chromium and playwright-core into ${e2eDir}`);
  execFileSync("bash", [path.join(repoDir, "tools", "code-server-setup.sh"), e2eDir], {
    stdio: ["ignore", "inherit", "inherit"],
    timeout: 15 * 60 * 1000,
  });
  if (!process.argv.includes("--no-package") || !fs.existsSync(vsix)) {
    log("packaging the extension");
    execFileSync("npm", ["run", "--silent", "package"], { cwd: extensionDir, stdio: ["ignore", "ignore", "inherit"] });
  }
}

function serverSettings() {
  const lsp = findOnPath("rdcd-lsp");
  if (lsp !== undefined && process.env.RDCD_E2E_PYTHON === undefined) {
    return { "rdcd.server.path": lsp };
  }
  const python = process.env.RDCD_E2E_PYTHON ?? findOnPath("python3") ?? findOnPath("python");
  if (python === undefined) {
    throw new Error("neither rdcd-lsp nor python3 is on PATH: install the project (pip install -e .)");
  }
  return { "rdcd.server.pythonPath": python };
}

function prepareWorkspace(root) {
  const userData = path.join(root, "user-data");
  const extensions = path.join(root, "extensions");
  const workspace = path.join(root, "workspace");
  fs.mkdirSync(path.join(userData, "User"), { recursive: true });
  fs.mkdirSync(extensions, { recursive: true });
  fs.mkdirSync(workspace, { recursive: true });
  for (const name of fs.readdirSync(path.join(repoDir, "examples"))) {
    if (name.endsWith(".rdcd")) {
      fs.copyFileSync(path.join(repoDir, "examples", name), path.join(workspace, name));
    }
  }
  const settings = {
    ...serverSettings(),
    "rdcd.simulate.config": "car7",
    "rdcd.simulate.duration": 8,
    "rdcd.simulate.obstacle": "wall:1",
    "rdcd.trace.server": "messages",
    "workbench.colorTheme": "Default Dark Modern",
    "workbench.startupEditor": "none",
    "workbench.tips.enabled": false,
    "workbench.secondarySideBar.defaultVisibility": "hidden",
    "workbench.welcomePage.walkthroughs.openOnInstall": false,
    "security.workspace.trust.enabled": false,
    "telemetry.telemetryLevel": "off",
    "chat.disableAIFeatures": true,
    "extensions.autoCheckUpdates": false,
    "extensions.autoUpdate": false,
    "update.mode": "none",
    "editor.hover.delay": 200,
    // Colours from the TextMate grammar only, so that the check below tests the grammar.
    "editor.semanticHighlighting.enabled": false,
    "editor.minimap.enabled": false,
    "files.autoSave": "off",
  };
  fs.writeFileSync(path.join(userData, "User", "settings.json"), JSON.stringify(settings, null, 2));
  // code-server is a remote window: machine-scoped settings such as rdcd.server.path count only in
  // the remote ("Machine") settings.
  fs.mkdirSync(path.join(userData, "Machine"), { recursive: true });
  fs.writeFileSync(path.join(userData, "Machine", "settings.json"), JSON.stringify(serverSettings(), null, 2));
  log(`server settings: ${JSON.stringify(serverSettings())}`);
  return { userData, extensions, workspace };
}

async function startCodeServer(dirs, root) {
  const codeServer = path.join(e2eDir, "bin", "code-server");
  const common = ["--user-data-dir", dirs.userData, "--extensions-dir", dirs.extensions];
  const install = spawnSync(codeServer, [...common, "--install-extension", vsix], { encoding: "utf8", timeout: 120000 });
  if (install.status !== 0 || !/successfully installed/i.test(install.stdout)) {
    throw new Error(`installing the vsix failed:\n${install.stdout}\n${install.stderr}`);
  }
  log("extension installed into code-server");
  const port = await freePort();
  const config = path.join(root, "code-server.yaml");
  fs.writeFileSync(config, "");
  const logFile = fs.openSync(path.join(artifacts, "code-server.log"), "w");
  const child = spawn(
    codeServer,
    [
      "--config", config,
      "--auth", "none",
      "--bind-addr", `127.0.0.1:${port}`,
      "--disable-telemetry",
      "--disable-update-check",
      "--disable-workspace-trust",
      "--disable-getting-started-override",
      ...common,
      dirs.workspace,
    ],
    { stdio: ["ignore", logFile, logFile], detached: true },
  );
  const url = `http://127.0.0.1:${port}`;
  await until("code-server to answer", async () => (await httpStatus(`${url}/healthz`)) === 200, { timeout: 60000, interval: 500 });
  log(`code-server ${child.pid} listens on ${url}`);
  return { child, url };
}

async function shot(page, name) {
  shotCount += 1;
  const file = path.join(artifacts, `${String(shotCount).padStart(2, "0")}-${name}.png`);
  await page.screenshot({ path: file }).catch((error) => log(`  screenshot ${name} failed: ${error.message}`));
  return file;
}

async function step(page, name, action) {
  const begun = Date.now();
  if (Date.now() - started > TOTAL_BUDGET_MS) {
    results.push({ name, ok: false, error: "skipped: the time budget is used up" });
    log(`SKIP ${name}: time budget used up`);
    return;
  }
  log(`step: ${name}`);
  try {
    const detail = await action();
    results.push({ name, ok: true, detail, ms: Date.now() - begun });
    log(`PASS ${name}${detail ? `: ${detail}` : ""}`);
    await shot(page, name);
  } catch (error) {
    results.push({ name, ok: false, error: String(error.stack ?? error) });
    log(`FAIL ${name}: ${String(error.message ?? error)}`);
    await shot(page, `${name}-FAILED`);
    await page.keyboard.press("Escape").catch(() => undefined);
  }
}

// ---- UI helpers -------------------------------------------------------------------------------

async function quickInput(page, open, text, rowMatch) {
  await retry(`quick input "${text}"`, async () => {
    await page.keyboard.press("Escape");
    await page.keyboard.press(open);
    const input = page.locator(".quick-input-widget .quick-input-box input");
    await input.waitFor({ state: "visible", timeout: 5000 });
    await input.fill(text);
    const row = page.locator(".quick-input-widget .monaco-list-row", { hasText: rowMatch }).first();
    await row.waitFor({ state: "visible", timeout: 8000 });
    await page.keyboard.press("Enter");
    await page.locator(".quick-input-widget").waitFor({ state: "hidden", timeout: 5000 });
  });
}

async function openFile(page, name) {
  await quickInput(page, "Control+P", name, name);
  await page.locator(`.tab.active[aria-label*="${name}"]`).waitFor({ state: "visible", timeout: 15000 });
  await page.locator(".monaco-editor .view-lines").first().waitFor({ state: "visible", timeout: 15000 });
  await page.locator(".monaco-editor textarea").first().focus();
}

async function runCommand(page, title) {
  // The command palette's text starts with ">"; filling the box replaces it, so type it again.
  await quickInput(page, "F1", `>${title}`, title);
}

async function goTo(page, line, column) {
  await retry(`go to ${line}:${column}`, async () => {
    await page.keyboard.press("Escape");
    await page.keyboard.press("Control+G");
    const input = page.locator(".quick-input-widget .quick-input-box input");
    await input.waitFor({ state: "visible", timeout: 5000 });
    await input.fill(`:${line}:${column}`);
    await sleep(300);
    await page.keyboard.press("Enter");
    await page.locator(".quick-input-widget").waitFor({ state: "hidden", timeout: 5000 });
    const position = await page.locator("#status\\.editor\\.selection").innerText();
    if (!position.includes(`Ln ${line}, Col ${column}`)) {
      throw new Error(`cursor is at ${position}`);
    }
  });
}

/** Error and warning counts from the status bar's problems item. */
async function problemCounts(page) {
  const label = (await page.locator("#status\\.problems").getAttribute("aria-label")) ?? "";
  if (/no problems/i.test(label)) {
    return { errors: 0, warnings: 0, label };
  }
  const errors = /(\d+)\s+errors?|errors?:\s*(\d+)/i.exec(label);
  const warnings = /(\d+)\s+warnings?|warnings?:\s*(\d+)/i.exec(label);
  return {
    errors: errors ? Number(errors[1] ?? errors[2]) : 0,
    warnings: warnings ? Number(warnings[1] ?? warnings[2]) : 0,
    label,
  };
}

async function serverRunning(page) {
  await until(
    "the RDCD status bar item to say the server runs",
    async () => (await page.locator('.statusbar-item[aria-label^="RDCD language server running"]').count()) > 0,
    { timeout: 60000 },
  );
}

/** The computed colour of the first rendered token with exactly this text. */
/* global document, getComputedStyle -- the callback runs in the page */
async function tokenColours(page, texts) {
  return page.evaluate((wanted) => {
    const colours = {};
    const spans = [...document.querySelectorAll(".monaco-editor .view-lines .view-line span span")];
    for (const text of wanted) {
      const span = spans.find((element) => element.textContent === text);
      colours[text] = span ? getComputedStyle(span).color : null;
    }
    const lines = document.querySelector(".monaco-editor .view-lines");
    colours["<default>"] = lines ? getComputedStyle(lines).color : null;
    return colours;
  }, texts);
}

function tokenLocator(page, text) {
  return page.locator(".monaco-editor .view-lines .view-line span span").filter({ hasText: new RegExp(`^${text}$`) }).first();
}

// ---- the test ---------------------------------------------------------------------------------

async function runChecks(page, url, workspace) {
  await retry("load the workbench", async () => {
    await page.goto(`${url}/?folder=${encodeURIComponent(workspace)}`, { timeout: 60000 });
    await page.locator(".monaco-workbench").waitFor({ state: "visible", timeout: 60000 });
    await page.locator(".explorer-folders-view, .explorer-viewlet").first().waitFor({ timeout: 30000 });
  }, { attempts: 2 });
  await sleep(2000);

  await step(page, "language-mode-and-colours", async () => {
    await openFile(page, "snake_wave.rdcd");
    await until("the language mode RDCD", async () =>
      ((await page.locator("#status\\.editor\\.mode").innerText().catch(() => "")).trim() === "RDCD"));
    await serverRunning(page);
    const status = await page.locator('.statusbar-item[aria-label^="RDCD language server running"]').first().getAttribute("aria-label");
    const expected = Object.keys(serverSettings())[0];
    if (!status?.includes(`from ${expected}`)) {
      throw new Error(`the server was not started from ${expected}: "${status}"`);
    }
    const colours = await until("coloured tokens", async () => {
      const found = await tokenColours(page, ["abstract", "role", "Segment", "self", "sizeof", "EVENT_PROXIMITY_0", "deployment"]);
      return Object.values(found).every((value) => value !== null) ? found : undefined;
    });
    const plain = colours["<default>"];
    for (const word of ["abstract", "role", "Segment", "deployment", "EVENT_PROXIMITY_0"]) {
      if (colours[word] === plain) {
        throw new Error(`"${word}" has the default colour ${plain}: ${JSON.stringify(colours)}`);
      }
    }
    if (colours["role"] === colours["Segment"]) {
      throw new Error(`the keyword and the role name have one colour: ${JSON.stringify(colours)}`);
    }
    return `${status}; mode RDCD; role ${colours["role"]}, Segment ${colours["Segment"]}, default ${plain}`;
  });

  await step(page, "hover-on-role", async () => {
    await page.mouse.move(5, 5);
    await retry("hover over Head", async () => {
      const head = tokenLocator(page, "Head");
      await head.waitFor({ state: "visible", timeout: 5000 });
      await head.hover();
      const hover = page.locator(".monaco-hover:visible .hover-contents, .monaco-hover:visible .monaco-hover-content").first();
      await hover.waitFor({ state: "visible", timeout: 8000 });
      await until("hover text about Head", async () => /Head/.test(await hover.innerText()), { timeout: 8000 });
    });
    const text = await page.locator(".monaco-hover:visible").first().innerText();
    return `hover: ${text.replace(/\s+/g, " ").slice(0, 120)}`;
  });

  await step(page, "completion-after-self", async () => {
    await page.mouse.move(5, 5);
    await page.keyboard.press("Escape");
    await goTo(page, 15, 20);
    await page.keyboard.press("Enter");
    await page.keyboard.type("self.", { delay: 60 });
    const labels = await retry("the suggestion list", async (attempt) => {
      if (attempt > 1) {
        await page.keyboard.press("Control+Space");
      }
      const rows = page.locator(".suggest-widget.visible .monaco-list-row");
      await rows.first().waitFor({ state: "visible", timeout: 8000 });
      await sleep(500);
      const found = await rows.evaluateAll((elements) => elements.map((element) => element.getAttribute("aria-label") ?? element.textContent ?? ""));
      const primitives = ["assumeRole", "center_position", "clearEvent", "connected", "disableEvent", "enableEvent", "handleEvent", "setLed", "sleep", "turnTowards"];
      const listed = primitives.filter((name) => found.some((label) => label.includes(name)));
      if (listed.length < 4) {
        throw new Error(`too few primitives in ${JSON.stringify(found)}`);
      }
      return listed;
    });
    await shot(page, "completion-list");
    await page.keyboard.press("Escape");
    for (let i = 0; i < 3; i++) {
      await page.keyboard.press("Control+Z");
    }
    return `primitives listed: ${labels.join(", ")}`;
  });

  await step(page, "diagnostics-error-and-fix", async () => {
    await page.keyboard.press("Escape");
    await until("the file to be back as it was", async () => {
      const dirty = await page.locator(".tab.active.dirty").count();
      if (dirty > 0) {
        await page.keyboard.press("Control+Z");
      }
      return dirty === 0;
    }, { timeout: 8000 });
    const before = await until("no errors before the edit", async () => {
      const counts = await problemCounts(page);
      return counts.errors === 0 ? counts : undefined;
    });
    await goTo(page, 10, 15);
    await page.keyboard.type("x");
    const broken = await until("an error in the Problems count", async () => {
      const counts = await problemCounts(page);
      return counts.errors > 0 ? counts : undefined;
    }, { timeout: 20000 });
    await until("a squiggle", async () => (await page.locator(".monaco-editor .squiggly-error").count()) > 0, { timeout: 10000 });
    await shot(page, "error-squiggle");
    const fixed = Date.now();
    await page.keyboard.press("Backspace");
    const after = await until("the Problems count to drop to zero", async () => {
      const counts = await problemCounts(page);
      return counts.errors === 0 ? counts : undefined;
    }, { timeout: 10000, interval: 100 });
    const dropMs = Date.now() - fixed;
    await until("the squiggle to go", async () => (await page.locator(".monaco-editor .squiggly-error").count()) === 0, { timeout: 5000 });
    return `before "${before.label}", broken "${broken.label}", after "${after.label}" ${dropMs} ms after the fix`;
  });

  await step(page, "show-bytecode", async () => {
    await page.locator(".monaco-editor textarea").first().focus();
    await runCommand(page, "RDCD: Show Bytecode");
    const tab = page.locator('.tab[aria-label*="snake_wave.rdcd.bytecode"]').first();
    await tab.waitFor({ state: "visible", timeout: 20000 });
    const group = page
      .locator(".editor-group-container")
      .filter({ has: page.locator('.tab.active[aria-label*="snake_wave.rdcd.bytecode"]') })
      .first();
    const text = await until("the listing", async () => {
      const content = await group.locator(".monaco-editor .view-lines").first().innerText().catch(() => "");
      return /fragment/.test(content) && /\b[0-9a-f]{2}\s+[A-Z_]{3,}/.test(content) ? content : undefined;
    }, { timeout: 30000 });
    return `listing: ${text.split("\n").slice(0, 2).join(" | ").replace(/\s+/g, " ").slice(0, 120)}`;
  });

  await step(page, "simulate-current-file", async () => {
    await openFile(page, "obstacle_avoidance.rdcd");
    await serverRunning(page);
    await runCommand(page, "RDCD: Simulate Current File");
    await page.locator(".notifications-toasts, .notification-toast").first().waitFor({ timeout: 15000 }).catch(() => undefined);
    await shot(page, "simulate-progress");
    const tab = page.locator('.tab[aria-label*="Simulation: obstacle_avoidance.rdcd"]').first();
    await tab.waitFor({ state: "visible", timeout: 240000 });
    const view = simulationView(page);
    const replay = await replayReady(view);
    const failed = await view.locator("p.error").count();
    if (failed > 0) {
      throw new Error(`the result view shows a failure: ${await view.locator("body").innerText()}`);
    }
    await shot(page, "simulate-replay");
    // the summary and the plot are in the second tab
    await view.locator('label[for="rdcd-tab-report"]').click();
    await view.locator("#roles table").waitFor({ state: "visible", timeout: 10000 });
    const width = await until("the plot image to load", async () => {
      const image = view.locator("img#trajectory");
      if ((await image.count()) === 0) {
        return undefined;
      }
      const natural = await image.evaluate((element) => (element.complete ? element.naturalWidth : 0));
      return natural > 0 ? natural : undefined;
    }, { timeout: 20000 });
    const roles = await view.locator("#roles table tbody").innerText();
    const summary = await view.locator("#summary").innerText();
    await shot(page, "simulate-summary-tab");
    await view.locator('label[for="rdcd-tab-replay"]').click();
    await view.locator(".rr-view canvas").waitFor({ state: "visible", timeout: 10000 });
    const consoleCheck = checkConsole();
    return `replay of ${replay.modules} modules over ${replay.duration} s, ${replay.events} events; ${consoleCheck}; ` +
      `plot ${width}px wide; roles: ${roles.replace(/\s+/g, " ").slice(0, 80)}; ${summary.replace(/\s+/g, " ").slice(0, 80)}`;
  });

  await step(page, "replay-event-reveals-line", async () => {
    const view = simulationView(page);
    await replayReady(view);
    // an event of the list that has a source line away from the cursor's line
    // the cursor first at 1:1 in the program's editor, the panel still beside it
    await page.locator('.tab[aria-label^="obstacle_avoidance.rdcd"]').first().click();
    await page.locator(".monaco-editor textarea").first().focus();
    await goTo(page, 1, 1);
    const before = await page.locator("#status\\.editor\\.selection").innerText();
    const cursorLine = 1;
    const rows = view.locator(".rr-events li[data-index]");
    await rows.first().waitFor({ state: "visible", timeout: 10000 });
    const texts = await rows.allInnerTexts();
    // a handler's line if the run has one (the detection), else any line but the cursor's
    const candidates = texts.map((text, index) => ({ index, text, line: Number(/\(line (\d+)\)/.exec(text)?.[1] ?? 0) }))
      .filter((row) => row.line > 0 && row.line !== cursorLine);
    const chosen = candidates.find((row) => /handler/.test(row.text)) ?? candidates[0];
    if (chosen === undefined) {
      throw new Error(`no event with a source line in ${texts.length} rows: ${texts.slice(0, 5).join(" | ")}`);
    }
    await rows.nth(chosen.index).click();
    await view.locator(".rr-source .rr-line-ref").waitFor({ state: "visible", timeout: 10000 });
    await until(`the editor's cursor on line ${chosen.line}`, async () => {
      const position = await page.locator("#status\\.editor\\.selection").innerText().catch(() => "");
      return position.includes(`Ln ${chosen.line},`);
    }, { timeout: 15000 });
    await page.locator('.tab.active[aria-label^="obstacle_avoidance.rdcd"]').first().waitFor({ timeout: 5000 });
    const shown = (await page.locator(".monaco-editor .view-overlays .current-line").count()) > 0;
    return `cursor was at "${before}"; clicked "${chosen.text.replace(/\s+/g, " ").slice(0, 80)}"; ` +
      `cursor on line ${chosen.line}${shown ? ", line highlighted" : ""}`;
  });

  await step(page, "open-last-replay", async () => {
    // close the panel and restart the server (it removes its temporary files): the replay is the kept copy
    const panelTab = page.locator('.tab[aria-label*="Simulation: obstacle_avoidance.rdcd"]').first();
    await panelTab.click();
    await panelTab.locator(".tab-actions .action-label").first().click();
    await panelTab.waitFor({ state: "detached", timeout: 10000 });
    await page.locator('.tab[aria-label^="obstacle_avoidance.rdcd"]').first().click();
    await page.locator('.tab.active[aria-label^="obstacle_avoidance.rdcd"]').first().waitFor({ timeout: 5000 });
    await runCommand(page, "RDCD: Restart Language Server");
    await serverRunning(page);
    await runCommand(page, "RDCD: Open Last Replay");
    await page.locator('.tab[aria-label*="Simulation: obstacle_avoidance.rdcd"]').first().waitFor({ state: "visible", timeout: 30000 });
    const replay = await replayReady(simulationView(page));
    for (const message of webviewConsole) {
      log(`  webview console: ${message.slice(0, 200)}`);
    }
    return `reopened after a server restart: ${replay.modules} modules, ${replay.events} events; ${checkConsole()}`;
  });
}

/** The debugger: a breakpoint set in the editor, F5's configuration (no launch.json), the world
 * stopped on that line with the modules as threads and the role in the Variables view, the replay
 * panel at the same moment, then on to the end. */
async function checkDebugger(page) {
  await step(page, "debug-breakpoint", async () => {
    // not openFile: the Simulate panel, if still open, has the file's name in its tab too
    await page.keyboard.press("Escape");
    await retry("open obstacle_avoidance.rdcd from the explorer", async () => {
      await page.locator('.explorer-folders-view .monaco-list-row[aria-label^="obstacle_avoidance.rdcd"]').first().click();
      await page.locator('.tab.active[aria-label^="obstacle_avoidance.rdcd"]').first().waitFor({ state: "visible", timeout: 8000 });
    });
    await page.locator(".monaco-editor textarea").first().focus();
    await goTo(page, 13, 1);
    await runCommand(page, "Debug: Toggle Breakpoint");
    await until("the breakpoint in the glyph margin", async () =>
      (await page.locator(".monaco-editor .codicon-debug-breakpoint").count()) > 0, { timeout: 10000 });
    // F5's command, picked by its exact title ("Debug: Select and Start Debugging" matches too)
    await retry("Debug: Start Debugging", async () => {
      await page.keyboard.press("Escape");
      await page.keyboard.press("F1");
      const input = page.locator(".quick-input-widget .quick-input-box input");
      await input.waitFor({ state: "visible", timeout: 5000 });
      await input.fill(">Debug: Start Debugging");
      const row = page.locator(".quick-input-widget .monaco-list-row").filter({ hasText: /^\s*Debug: Start Debugging/ }).first();
      await row.waitFor({ state: "visible", timeout: 8000 });
      await row.click();
      await page.locator(".quick-input-widget").waitFor({ state: "hidden", timeout: 5000 }).catch(async () => {
        // a picker of debuggers: ours
        await page.locator(".quick-input-widget .monaco-list-row", { hasText: "RDCD" }).first().click({ timeout: 5000 });
      });
    });
    await until("the editor stopped on line 13", async () => {
      const frame = await page.locator(".monaco-editor .codicon-debug-stackframe").count();
      const position = await page.locator("#status\\.editor\\.selection").innerText().catch(() => "");
      return frame > 0 && position.includes("Ln 13,");
    }, { timeout: 90000 });
    const threads = await until("module threads in the call stack", async () => {
      const rows = await page.locator(".debug-call-stack .monaco-list-row").allInnerTexts();
      return rows.filter((text) => /module \d+/.test(text)).length >= 2 ? rows : undefined;
    }, { timeout: 20000 });
    const variables = await until("the role in the Variables view", async () => {
      const module = page.locator(".debug-variables .monaco-list-row", { hasText: /^\s*Module\s*$/ }).first();
      if ((await module.getAttribute("aria-expanded").catch(() => null)) === "false") {
        await module.click();
      }
      const rows = await page.locator(".debug-variables .monaco-list-row").allInnerTexts();
      return rows.some((text) => /role/.test(text) && /(Left|Right)Wheel/.test(text)) ? rows : undefined;
    }, { timeout: 20000 });
    // the Simulate panel, still open on the last run of this file (same settings, so the same run),
    // follows the debugger: the time of the stop that the call stack shows on the stopped module
    // ("breakpoint at t = 3.100 s"), with that module's panel open
    let seen = "nothing";
    const moment = await until("the replay at the stop's moment", async () => {
      const rows = await page.locator(".debug-call-stack .monaco-list-row").allInnerTexts();
      const stopped = rows.map((text) => /module (\d+)[\s\S]*breakpoint at t = ([\d.]+) s/i.exec(text)).find((m) => m !== null);
      const state = await simulationView(page).locator("html").evaluate(() => ({
        t: window.rdcdReplay.time(),
        heading: document.querySelector(".rr-module h3")?.textContent ?? "",
      }), undefined, { timeout: 2000 }).catch((error) => { seen = `the replay: ${error.message.slice(0, 200)}`; });
      if (state !== undefined) {
        seen = `stopped ${stopped ? `module ${stopped[1]} at ${stopped[2]} s` : "nowhere"}, replay at ${state.t} s, "${state.heading}"`;
      }
      if (stopped === undefined || stopped === null || state === undefined) {
        return undefined;
      }
      const same = Math.abs(state.t - Number(stopped[2])) < 0.0006 && state.heading.startsWith(`Module ${stopped[1]}`);
      return same ? { t: state.t, id: Number(stopped[1]) } : undefined;
    }, { timeout: 20000 }).catch((error) => {
      throw new Error(`${error.message}; last seen: ${seen}`);
    });
    await shot(page, "debug-stopped");
    // the breakpoint off, on to the end of the run
    await page.locator(".monaco-editor textarea").first().focus();
    await goTo(page, 13, 1);
    await runCommand(page, "Debug: Toggle Breakpoint");
    await until("the breakpoint gone", async () =>
      (await page.locator(".monaco-editor .codicon-debug-breakpoint").count()) === 0, { timeout: 10000 });
    await page.locator(".debug-toolbar .codicon-debug-continue").first().click();
    await until("the debug session to end", async () =>
      (await page.locator(".debug-toolbar").count()) === 0 || !(await page.locator(".debug-toolbar").first().isVisible()),
    { timeout: 120000 });
    return `replay at t = ${moment.t.toFixed(3)} s on module ${moment.id}; threads: ${threads.slice(0, 3).join(" | ").replace(/\s+/g, " ")}; ` +
      `variables: ${variables.slice(0, 3).join(" | ").replace(/\s+/g, " ")}`;
  });
}

/** Console messages of the policy blocking something, anywhere in the page and its frames. */
const policyViolations = [];
/** Console messages from webviews, and their errors. */
const webviewConsole = [];
const webviewErrors = [];

function checkConsole() {
  if (policyViolations.length > 0) {
    throw new Error(`the policy blocked something: ${policyViolations.join(" | ")}`);
  }
  if (webviewErrors.length > 0) {
    throw new Error(`errors in the webview's console: ${webviewErrors.join(" | ")}`);
  }
  return `${webviewConsole.length} webview console message(s), no error, nothing blocked by the policy`;
}

/** The Simulate panel's document (a webview: an iframe holding the active frame). */
function simulationView(page) {
  return page.frameLocator("iframe.webview.ready").last().frameLocator("iframe#active-frame");
}

/** Waits for the replay in the panel to start; its figures from the test hook window.rdcdReplay. */
async function replayReady(view) {
  const html = view.locator("html");
  const state = await until("the replay to start", async () => {
    const value = await html.getAttribute("data-replay-ready", { timeout: 2000 }).catch(() => null);
    return value === "true" || value === "error" ? value : undefined;
  }, { timeout: 60000 });
  /* global window -- the callback runs in the webview */
  const hook = await html.evaluate(() => {
    const replay = window.rdcdReplay;
    return replay && replay.ready
      ? { ready: true, modules: replay.modules.length, duration: replay.duration, events: replay.events().length }
      : { ready: false, error: replay?.error };
  });
  if (state !== "true" || !hook.ready) {
    throw new Error(`the replay did not start: ${hook.error ?? state}`);
  }
  return hook;
}

/** The last step: a server path that does not exist gives one error with a button to the setting. */
async function checkMissingServer(page) {
  await step(page, "missing-server-message", async () => {
    // Through the Settings editor: code-server has no file watcher, so edits of settings.json on
    // disk would go unnoticed, while the Settings editor writes through the configuration service.
    await runCommand(page, "Preferences: Open Settings (UI)");
    const editor = page.locator(".settings-editor");
    await editor.waitFor({ state: "visible", timeout: 15000 });
    await sleep(500);
    await page.keyboard.insertText("rdcd.server.path");
    await editor.locator(".settings-tabs-widget .action-label", { hasText: "Remote" }).first().click();
    const input = editor.locator('.setting-item-contents[data-key="rdcd.server.path"] input, .setting-item-string input').first();
    await input.waitFor({ state: "visible", timeout: 15000 });
    await input.fill("/nonexistent/rdcd-lsp");
    await input.press("Tab");
    const toast = page.locator(".notification-toast", { hasText: "RDCD language server was not found" }).first();
    await toast.waitFor({ state: "visible", timeout: 30000 });
    const text = (await toast.innerText()).replace(/\s+/g, " ");
    const errorToasts = await page.locator(".notification-toast", { hasText: "RDCD" }).count();
    await shot(page, "missing-server-toast");
    await toast.locator(".monaco-button", { hasText: "Open Settings" }).click();
    await until("the settings editor on rdcd.server", async () => {
      const search = await page.locator(".settings-editor .suggest-input-container .view-lines").first().innerText().catch(() => "");
      return search.includes("rdcd.server");
    }, { timeout: 15000 });
    const status = await page.locator('.statusbar-item[aria-label^="RDCD language server"]').first().getAttribute("aria-label");
    return `${errorToasts} RDCD notification(s): "${text.slice(0, 140)}"; status: ${status}`;
  });
}

function collectLogs(userData) {
  // The extension host's logs (including the RDCD output channel) help when a step failed.
  const logs = path.join(userData, "logs");
  if (!fs.existsSync(logs)) {
    return;
  }
  const target = path.join(artifacts, "vscode-logs");
  fs.cpSync(logs, target, { recursive: true });
}

async function main() {
  fs.rmSync(artifacts, { recursive: true, force: true });
  fs.mkdirSync(artifacts, { recursive: true });
  setup();
  const root = fs.mkdtempSync(path.join(os.tmpdir(), "rdcd-e2e-"));
  const dirs = prepareWorkspace(root);
  let codeServer;
  let browser;
  try {
    codeServer = await startCodeServer(dirs, root);
    const require = createRequire(path.join(e2eDir, "pw", "node_modules", "noop.js"));
    const { chromium } = require("playwright-core");
    browser = await chromium.launch({
      executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
      headless: process.env.RDCD_E2E_HEADED !== "1",
      args: [
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
      ],
    });
    const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
    page.on("console", (message) => {
      const where = message.location().url;
      const text = `${where}: ${message.text().slice(0, 300)}`;
      if (/Content.Security.Policy|Refused to/i.test(message.text())) {
        log(`  console (policy): ${text}`);
        policyViolations.push(text);
      } else if (/\/webview\//.test(where)) {
        webviewConsole.push(`${message.type()} ${message.text().slice(0, 200)} (${where.split("?")[0]})`);
        if (message.type() === "error") {
          log(`  console (webview error): ${text}`);
          webviewErrors.push(text);
        }
      }
    });
    page.setDefaultTimeout(20000);
    await runChecks(page, codeServer.url, dirs.workspace);
    if (process.argv.includes("--docs-screenshot")) {
      const docs = path.join(repoDir, "docs", "vscode.png");
      await page.screenshot({ path: docs });
      log(`wrote ${docs} (${fs.statSync(docs).size} bytes)`);
    }
    await checkDebugger(page);
    await checkMissingServer(page);
  } finally {
    await browser?.close().catch(() => undefined);
    if (codeServer?.child.pid !== undefined) {
      try {
        process.kill(-codeServer.child.pid, "SIGTERM");
      } catch {
        // already gone
      }
    }
    collectLogs(dirs.userData);
    fs.rmSync(root, { recursive: true, force: true });
  }
  const failed = results.filter((result) => !result.ok);
  console.log("");
  for (const result of results) {
    console.log(`${result.ok ? "ok  " : "FAIL"} ${result.name}${result.ok ? ` (${result.ms} ms)` : `\n     ${result.error.split("\n").slice(0, 3).join("\n     ")}`}`);
  }
  console.log(`e2e: ${results.length - failed.length} passed, ${failed.length} failed`);
  console.log(`(total ${((Date.now() - started) / 1000).toFixed(0)} s; screenshots in ${artifacts})`);
  process.exitCode = failed.length === 0 && results.length > 0 ? 0 : 1;
}

main().catch((error) => {
  console.error(error);
  process.exitCode = 1;
});
