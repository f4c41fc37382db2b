import * as assert from "node:assert/strict";
import { buildSimulateArgs, parseSimulateResult, SIMULATE_DEFAULTS } from "../../src/simulateArgs";

describe("buildSimulateArgs", () => {
  it("passes the settings through as [uri, {config, obstacle, duration, seed}]", () => {
    const args = buildSimulateArgs("file:///w/a.rdcd", { config: "car11", obstacle: "box:0,1,0.2,0.2", duration: 8, seed: 42 });
    assert.deepEqual(args, ["file:///w/a.rdcd", { config: "car11", obstacle: "box:0,1,0.2,0.2", duration: 8, seed: 42 }]);
  });

  it("adds the packet loss only when it is in (0, 1]", () => {
    assert.equal(buildSimulateArgs("u", { packetLoss: 0.1 })[1].packetLoss, 0.1);
    assert.equal("packetLoss" in buildSimulateArgs("u", { packetLoss: 0 })[1], false);
    assert.equal("packetLoss" in buildSimulateArgs("u", { packetLoss: 2 })[1], false);
  });

  it("adds the world only when one is set", () => {
    assert.equal(buildSimulateArgs("u", { world: "lattice" })[1].world, "lattice");
    assert.equal("world" in buildSimulateArgs("u", { world: "" })[1], false);
  });

  it("turns a distance into a wall and null into none", () => {
    assert.equal(buildSimulateArgs("u", { obstacle: 1.5 })[1].obstacle, "wall:1.5");
    assert.equal(buildSimulateArgs("u", { obstacle: null })[1].obstacle, "none");
    assert.equal(buildSimulateArgs("u", { obstacle: " none " })[1].obstacle, "none");
  });

  it("falls back to the defaults for missing or wrong values", () => {
    const [, options] = buildSimulateArgs("u", { config: "  ", obstacle: -1, duration: 0, seed: "x" });
    assert.deepEqual(options, { ...SIMULATE_DEFAULTS });
    assert.deepEqual(buildSimulateArgs("u", {})[1], { ...SIMULATE_DEFAULTS });
    assert.equal(buildSimulateArgs("u", { duration: Number.NaN })[1].duration, SIMULATE_DEFAULTS.duration);
    assert.equal(buildSimulateArgs("u", { seed: 3.7 })[1].seed, 3);
  });
});

describe("parseSimulateResult", () => {
  it("reads {report, plotPath}", () => {
    const result = parseSimulateResult({ report: { steps: 3 }, plotPath: "/tmp/p.png" });
    assert.deepEqual(result, { report: { steps: 3 }, plotPath: "/tmp/p.png" });
  });

  it("accepts the report as JSON text and a missing plot", () => {
    const result = parseSimulateResult({ report: '{"a": 1}', plotPath: null });
    assert.deepEqual(result, { report: { a: 1 }, plotPath: undefined });
  });

  it("wraps a report that is not an object", () => {
    assert.deepEqual(parseSimulateResult({ report: "not json" }).report, { text: "not json" });
    assert.deepEqual(parseSimulateResult({ report: [1, 2] }).report, { result: [1, 2] });
  });

  it("rejects an empty answer", () => {
    assert.throws(() => parseSimulateResult(null), /no simulation result/);
  });
});
