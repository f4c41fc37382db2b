import * as assert from "node:assert/strict";
import * as fs from "node:fs";
import * as path from "node:path";

const root = path.resolve(__dirname, "..", "..", "..");
const read = (file: string): unknown => JSON.parse(fs.readFileSync(path.join(root, file), "utf8")) as unknown;

interface Command { command: string; enablement?: string }
interface MenuItem { command: string; when?: string }
interface Manifest {
  main: string;
  engines: { vscode: string };
  capabilities: { untrustedWorkspaces: { supported: string | boolean; restrictedConfigurations?: string[] } };
  contributes: {
    languages: { id: string; extensions: string[]; configuration: string }[];
    grammars: { language: string; scopeName: string; path: string }[];
    snippets: { language: string; path: string }[];
    commands: Command[];
    menus: Record<string, MenuItem[]>;
    configuration: { properties: Record<string, { default?: unknown }> };
    problemMatchers: { name: string; pattern: { regexp: string; file: number; line: number; column: number; severity: number; code: number; message: number } }[];
  };
}

const manifest = read("package.json") as Manifest;

describe("package.json", () => {
  it("contributes the rdcd language with its grammar, configuration and snippets", () => {
    const language = manifest.contributes.languages.find((item) => item.id === "rdcd");
    assert.ok(language);
    assert.deepEqual(language.extensions, [".rdcd"]);
    assert.ok(fs.existsSync(path.join(root, language.configuration)));
    const grammar = manifest.contributes.grammars[0];
    assert.ok(grammar);
    assert.equal(grammar.scopeName, "source.rdcd");
    assert.equal((read(grammar.path) as { scopeName: string }).scopeName, "source.rdcd");
    for (const snippet of manifest.contributes.snippets) {
      assert.ok(Object.keys(read(snippet.path) as object).length >= 8);
    }
    read(language.configuration);
    assert.equal(manifest.main, "./dist/extension.js");
    assert.equal(manifest.engines.vscode, "^1.90.0");
  });

  it("has the settings and commands of the extension", () => {
    const settings = Object.keys(manifest.contributes.configuration.properties).sort();
    for (const name of [
      "rdcd.server.path",
      "rdcd.server.pythonPath",
      "rdcd.server.args",
      "rdcd.inlayHints.fragmentSizes",
      "rdcd.target",
      "rdcd.simulate.config",
      "rdcd.simulate.obstacle",
      "rdcd.simulate.duration",
      "rdcd.simulate.vm",
      "rdcd.trace.server",
    ]) {
      assert.ok(settings.includes(name), name);
    }
    const commands = manifest.contributes.commands.map((item) => item.command);
    for (const name of ["rdcd.simulateCurrentFile", "rdcd.viewBytecode", "rdcd.restartServer"]) {
      assert.ok(commands.includes(name), name);
    }
    for (const items of Object.values(manifest.contributes.menus)) {
      for (const item of items) {
        assert.ok(commands.includes(item.command), `menu entry for unknown command ${item.command}`);
      }
    }
    const run = manifest.contributes.menus["editor/title/run"]?.[0];
    assert.equal(run?.command, "rdcd.simulateCurrentFile");
  });

  it("does not clash with the server's executeCommand names", () => {
    const commands = manifest.contributes.commands.map((item) => item.command);
    assert.ok(!commands.includes("rdcd.simulate"));
    assert.ok(!commands.includes("rdcd.showBytecode"));
  });

  it("limits untrusted workspaces: no simulation, no server path from the workspace", () => {
    assert.equal(manifest.capabilities.untrustedWorkspaces.supported, "limited");
    assert.deepEqual(manifest.capabilities.untrustedWorkspaces.restrictedConfigurations?.sort(), [
      "rdcd.server.args",
      "rdcd.server.path",
      "rdcd.server.pythonPath",
    ]);
    const simulate = manifest.contributes.commands.find((item) => item.command === "rdcd.simulateCurrentFile");
    assert.match(simulate?.enablement ?? "", /isWorkspaceTrusted/);
  });

  it("has a problem matcher for `rdcd check` output", () => {
    const matcher = manifest.contributes.problemMatchers.find((item) => item.name === "rdcd");
    assert.ok(matcher);
    const match = new RegExp(matcher.pattern.regexp).exec(
      "examples/figure5_verbatim.rdcd:42:1: error[E0102]: unexpected '}': this brace closes nothing",
    );
    assert.ok(match);
    assert.equal(match[matcher.pattern.file], "examples/figure5_verbatim.rdcd");
    assert.equal(match[matcher.pattern.line], "42");
    assert.equal(match[matcher.pattern.column], "1");
    assert.equal(match[matcher.pattern.severity], "error");
    assert.equal(match[matcher.pattern.code], "E0102");
    assert.equal(match[matcher.pattern.message], "unexpected '}': this brace closes nothing");
    const warning = new RegExp(matcher.pattern.regexp).exec("/abs/a b.rdcd:3:14: warning[W0301]: dead role 'X'");
    assert.equal(warning?.[matcher.pattern.file], "/abs/a b.rdcd");
    assert.equal(new RegExp(matcher.pattern.regexp).exec("a.rdcd: 3 files checked"), null);
  });
});

describe("grammar test files", () => {
  it("include unchanged copies of the project's examples", () => {
    const examples = path.join(root, "..", "examples");
    if (!fs.existsSync(examples)) {
      return;
    }
    const names = fs.readdirSync(examples).filter((name) => name.endsWith(".rdcd"));
    assert.ok(names.length > 0);
    for (const name of names) {
      const copy = path.join(root, "test", "grammar", name);
      assert.ok(fs.existsSync(copy), `test/grammar/${name} is missing: copy it and run npm run test:grammar:update`);
      assert.equal(fs.readFileSync(copy, "utf8"), fs.readFileSync(path.join(examples, name), "utf8"), `${name} changed`);
    }
  });
});
