import * as assert from "node:assert/strict";
import * as fs from "node:fs";
import * as path from "node:path";
import { adapterCommand, completeConfiguration, type SimulateSettings } from "../../src/debugConfig";
import type { ServerCommand } from "../../src/serverCommand";

const probe = (files: string[], onPath: Record<string, string> = {}) => ({
  isExecutable: (p: string) => files.includes(p),
  findOnPath: (name: string) => onPath[name],
});

const settings: SimulateSettings = {
  config: "car11", obstacle: "wall:0.5", duration: 12, seed: 3, world: "", packetLoss: 0.1, vm: "", target: "default",
};

describe("adapterCommand", () => {
  it("runs the language server's interpreter with -m rdcd_core dap", () => {
    for (const source of ["rdcd.server.pythonPath", "python extension"] as const) {
      assert.deepEqual(adapterCommand({ command: "/venv/bin/python", args: ["-m", "server"], source }, probe([])), {
        command: "/venv/bin/python", args: ["-m", "rdcd_core", "dap"],
      });
    }
  });

  it("takes the rdcd beside rdcd-lsp, else rdcd on PATH, else says what is missing", () => {
    const server: ServerCommand = { command: "/opt/rdcd/bin/rdcd-lsp", args: [], source: "rdcd.server.path" };
    assert.deepEqual(adapterCommand(server, probe(["/opt/rdcd/bin/rdcd"])), { command: "/opt/rdcd/bin/rdcd", args: ["dap"] });
    assert.deepEqual(adapterCommand(server, probe([], { rdcd: "/usr/bin/rdcd" })), { command: "/usr/bin/rdcd", args: ["dap"] });
    const missing = adapterCommand(server, probe([]));
    assert.ok("error" in missing && /rdcd/.test(missing.error));
  });
});

describe("completeConfiguration", () => {
  it("debugs the active file with the simulate settings when there is no launch.json", () => {
    assert.deepEqual(completeConfiguration({}, settings, "/ws/a.rdcd"), {
      type: "rdcd", request: "launch", name: "Debug RDCD program", program: "/ws/a.rdcd",
      config: "car11", obstacle: "wall:0.5", duration: 12, seed: 3, packetLoss: 0.1, target: "default",
    });
    assert.equal(completeConfiguration({}, settings, undefined), undefined);
  });

  it("keeps what launch.json says and fills in the rest", () => {
    const config = completeConfiguration(
      { type: "rdcd", request: "launch", name: "x", program: "/p.rdcd", duration: 5, world: "lattice" },
      { ...settings, world: "physics", vm: "original" }, undefined,
    );
    assert.ok(config !== undefined);
    assert.equal(config["duration"], 5);
    assert.equal(config["world"], "lattice");
    assert.equal(config["vm"], "original");
    assert.equal(config["config"], "car11");
  });
});

describe("the debugger in package.json", () => {
  it("contributes type rdcd with breakpoints in .rdcd files and every launch attribute the adapter reads", () => {
    const manifest = JSON.parse(fs.readFileSync(path.resolve(__dirname, "..", "..", "..", "package.json"), "utf8")) as {
      activationEvents: string[];
      contributes: { breakpoints: { language: string }[]; debuggers: { type: string; languages: string[];
        configurationAttributes: { launch: { properties: Record<string, unknown> } }; configurationSnippets: unknown[] }[] };
    };
    assert.deepEqual(manifest.contributes.breakpoints, [{ language: "rdcd" }]);
    const debuggerEntry = manifest.contributes.debuggers.find((d) => d.type === "rdcd");
    assert.ok(debuggerEntry);
    assert.deepEqual(debuggerEntry.languages, ["rdcd"]);
    assert.deepEqual(Object.keys(debuggerEntry.configurationAttributes.launch.properties).sort(), [
      "changes", "config", "duration", "noDebug", "obstacle", "packetLoss", "program", "seed", "stopOnEntry", "target", "vm",
      "world",
    ]);
    assert.ok(debuggerEntry.configurationSnippets.length >= 2);
    assert.ok(manifest.activationEvents.includes("onDebugResolve:rdcd"));
  });
});
