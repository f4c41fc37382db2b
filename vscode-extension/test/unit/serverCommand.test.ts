import * as assert from "node:assert/strict";
import { expandPath, findServerCommand, pathCandidates, type ServerProbe } from "../../src/serverCommand";

function probe(overrides: Partial<ServerProbe> & { files?: string[]; path?: Record<string, string>; canRun?: string[] } = {}): ServerProbe {
  const files = new Set(overrides.files ?? []);
  return {
    selectedPython: overrides.selectedPython,
    homeDir: "/home/u",
    workspaceFolder: "/ws",
    isExecutable: (path) => files.has(path),
    findOnPath: (name) => overrides.path?.[name],
    canRunServerModule: (python) => Promise.resolve((overrides.canRun ?? []).includes(python)),
  };
}

const none = { path: "", pythonPath: "", args: [] as string[] };

describe("findServerCommand", () => {
  it("uses rdcd.server.path first, with the extra arguments", async () => {
    const found = await findServerCommand(
      { ...none, path: "~/bin/rdcd-lsp", pythonPath: "/usr/bin/python3", args: ["--log", "debug"] },
      probe({ files: ["/home/u/bin/rdcd-lsp", "/usr/bin/python3"] }),
    );
    assert.deepEqual(found, { command: "/home/u/bin/rdcd-lsp", args: ["--log", "debug"], source: "rdcd.server.path" });
  });

  it("looks a bare server name up on PATH", async () => {
    const found = await findServerCommand({ ...none, path: "rdcd-lsp" }, probe({ path: { "rdcd-lsp": "/opt/bin/rdcd-lsp" } }));
    assert.deepEqual(found, { command: "/opt/bin/rdcd-lsp", args: [], source: "rdcd.server.path" });
  });

  it("reports a wrong rdcd.server.path instead of falling back", async () => {
    const found = await findServerCommand(
      { ...none, path: "/nope/rdcd-lsp" },
      probe({ path: { "rdcd-lsp": "/opt/bin/rdcd-lsp" } }),
    );
    assert.ok("error" in found);
    assert.equal(found.setting, "rdcd.server.path");
    assert.match(found.error, /\/nope\/rdcd-lsp/);
  });

  it("runs `python -m server` with rdcd.server.pythonPath", async () => {
    const found = await findServerCommand(
      { ...none, pythonPath: "${workspaceFolder}/.venv/bin/python", args: ["-v"] },
      probe({ files: ["/ws/.venv/bin/python"] }),
    );
    assert.deepEqual(found, { command: "/ws/.venv/bin/python", args: ["-m", "server", "-v"], source: "rdcd.server.pythonPath" });
  });

  it("reports a wrong rdcd.server.pythonPath", async () => {
    const found = await findServerCommand({ ...none, pythonPath: "/missing/python" }, probe());
    assert.ok("error" in found);
    assert.equal(found.setting, "rdcd.server.pythonPath");
  });

  it("uses the selected interpreter only when it has the server module", async () => {
    const withModule = await findServerCommand(none, probe({ selectedPython: "/env/bin/python", canRun: ["/env/bin/python"] }));
    assert.deepEqual(withModule, { command: "/env/bin/python", args: ["-m", "server"], source: "python extension" });
    const without = await findServerCommand(
      none,
      probe({ selectedPython: "/env/bin/python", path: { "rdcd-lsp": "/usr/local/bin/rdcd-lsp" } }),
    );
    assert.deepEqual(without, { command: "/usr/local/bin/rdcd-lsp", args: [], source: "PATH" });
  });

  it("gives one clear error pointing at the settings when nothing is found", async () => {
    const found = await findServerCommand(none, probe());
    assert.ok("error" in found);
    assert.equal(found.setting, "rdcd.server");
    assert.match(found.error, /rdcd-lsp/);
    assert.match(found.error, /rdcd\.server\.path/);
  });
});

describe("expandPath and pathCandidates", () => {
  it("expands ~, ${userHome} and ${workspaceFolder}", () => {
    const env = { homeDir: "/h", workspaceFolder: "/w" };
    assert.equal(expandPath(" ~/x ", env), "/h/x");
    assert.equal(expandPath("${userHome}/y", env), "/h/y");
    assert.equal(expandPath("${workspaceFolder}/z", env), "/w/z");
    assert.equal(expandPath("/abs", env), "/abs");
  });

  it("lists PATH candidates per platform", () => {
    assert.deepEqual(pathCandidates("rdcd-lsp", "/a:/b/::/c", "linux"), ["/a/rdcd-lsp", "/b/rdcd-lsp", "/c/rdcd-lsp"]);
    assert.deepEqual(pathCandidates("rdcd-lsp", "C:\\x", "win32").slice(0, 2), ["C:\\x\\rdcd-lsp.exe", "C:\\x\\rdcd-lsp.cmd"]);
  });
});
