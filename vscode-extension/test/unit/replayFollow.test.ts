import * as assert from "node:assert/strict";
import * as path from "node:path";
import { MOMENT_EVENT, parseMoment, runDifferences, samePath, seekMessage, sessionProgram } from "../../src/replayFollow";

describe("parseMoment", () => {
  it("reads the time and the module of an rdcd/moment event", () => {
    assert.deepEqual(parseMoment(MOMENT_EVENT, { t: 3.05, module: 4 }), { t: 3.05, module: 4, run: undefined });
    assert.deepEqual(parseMoment(MOMENT_EVENT, { t: 0, module: null, run: { seed: 1 } }), { t: 0, module: null, run: { seed: 1 } });
    assert.deepEqual(parseMoment(MOMENT_EVENT, { t: 0, module: null, run: [1] }), { t: 0, module: null, run: undefined });
  });

  it("ignores other events and malformed bodies", () => {
    assert.equal(parseMoment("stopped", { t: 1, module: 0 }), undefined);
    for (const body of [undefined, null, [], "t=1", {}, { t: "1", module: 0 }, { t: -1, module: 0 }, { t: Number.NaN, module: 0 },
      { t: Number.POSITIVE_INFINITY, module: 0 }, { t: 1 }, { t: 1, module: 1.5 }, { t: 1, module: -1 }, { t: 1, module: "4" }]) {
      assert.equal(parseMoment(MOMENT_EVENT, body), undefined, JSON.stringify(body));
    }
  });
});

describe("sessionProgram", () => {
  it("resolves the launch's program against its cwd", () => {
    const root = path.resolve("/ws");
    assert.equal(sessionProgram({ program: path.join(root, "a.rdcd") }), path.join(root, "a.rdcd"));
    assert.equal(sessionProgram({ program: "robots/a.rdcd", cwd: root }), path.join(root, "robots", "a.rdcd"));
    assert.equal(sessionProgram({ program: "a.rdcd" }, root), path.join(root, "a.rdcd"));
    assert.equal(sessionProgram({ program: "" }, root), undefined);
    assert.equal(sessionProgram({ program: 3 }, root), undefined);
    assert.equal(sessionProgram({}), undefined);
  });
});

describe("seekMessage", () => {
  const file = path.resolve("/ws/examples/obstacle_avoidance.rdcd");

  it("tells the replay to seek when the panel shows a run of the debugged file", () => {
    assert.deepEqual(seekMessage({ t: 3.012, module: 2 }, file, file, false), { type: "rdcd/seek", t: 3.012, module: 2 });
    assert.deepEqual(seekMessage({ t: 0, module: null }, file, path.join(path.dirname(file), ".", path.basename(file)), false), {
      type: "rdcd/seek", t: 0, module: null,
    });
  });

  it("says nothing when the panel shows another file or nothing", () => {
    const other = path.resolve("/ws/examples/snake_wave.rdcd");
    assert.equal(seekMessage({ t: 1, module: 0 }, file, other, false), undefined);
    assert.equal(seekMessage({ t: 1, module: 0 }, file, undefined, false), undefined);
    assert.equal(seekMessage({ t: 1, module: 0 }, undefined, file, false), undefined);
  });

  it("ignores letter case only where the file system does", () => {
    assert.equal(samePath(file, file.toUpperCase(), false), false);
    assert.equal(samePath(file, file.toUpperCase(), true), true);
    assert.notEqual(seekMessage({ t: 1, module: 0 }, file, file.toUpperCase(), true), undefined);
  });
});

describe("runDifferences", () => {
  const report = { world: "physics", vm: "", target: "default", config: "car7", entry: 0, obstacle: "wall:1", duration_s: 20,
    seed: 0, packet_loss: 0, modules: [] };
  const debugged = { world: "physics", vm: "", target: "default", config: "car7", entry: 0, obstacle: "wall:1", duration_s: 20,
    seed: 0, packet_loss: 0, source_sha256: "ab12".repeat(16) };

  it("finds nothing when the replay's run is the debugged run", () => {
    assert.deepEqual(runDifferences(debugged, report, "ab12".repeat(8)), []);
  });

  it("names each option that differs, and a different program text", () => {
    assert.deepEqual(runDifferences({ ...debugged, duration_s: 8, world: "lattice" }, report, "ab12".repeat(8)), [
      'world "physics" in the replay, "lattice" in the debugger',
      "duration_s 20 in the replay, 8 in the debugger",
    ]);
    assert.deepEqual(runDifferences(debugged, report, "ffff".repeat(8)), ["the program text"]);
    assert.deepEqual(runDifferences({ ...debugged, packet_loss: 0.1 }, { ...report, packet_loss: undefined }, undefined), [
      "packet_loss unset in the replay, 0.1 in the debugger",
    ]);
  });

  it("says nothing when the adapter did not name its run", () => {
    assert.deepEqual(runDifferences(undefined, report, "0".repeat(32)), []);
  });
});
