import * as assert from "node:assert/strict";
import { buildSimulateArgs, isCancelledRequest, parseSimulateResult, SIMULATE_DEFAULTS } from "../../src/simulateArgs";

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

  it("adds the VM profile only when one is set", () => {
    assert.equal(buildSimulateArgs("u", { vm: "original" })[1].vm, "original");
    assert.equal("vm" in buildSimulateArgs("u", { vm: "" })[1], false);
    assert.equal("vm" in buildSimulateArgs("u", { vm: 3 })[1], false);
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
  const report = { config: "car7", modules: [{ id: 0, final_role: null, lattice: [0, 0, 0] }], fragments: [{ name: "f", size: 3 }] };

  it("reads {report, plotPath}", () => {
    assert.deepEqual(parseSimulateResult({ report, plotPath: "/tmp/p.png" }), { report, plotPath: "/tmp/p.png" });
  });

  it("reads a missing plot as null", () => {
    assert.deepEqual(parseSimulateResult({ report, plotPath: null }), { report, plotPath: null });
  });

  it("rejects an answer without a report", () => {
    assert.throws(() => parseSimulateResult(null), /no simulation report/);
    assert.throws(() => parseSimulateResult({ report: '{"a": 1}', plotPath: null }), /no simulation report/);
  });

  it("rejects a report without its modules and fragments, and a plot path that is not a string", () => {
    assert.throws(() => parseSimulateResult({ report: { modules: [] }, plotPath: null }), /not \{report/);
    assert.throws(() => parseSimulateResult({ report: { ...report, modules: [{ id: "0" }] }, plotPath: null }), /not \{report/);
    assert.throws(() => parseSimulateResult({ report: { ...report, fragments: [{ name: "f" }] }, plotPath: null }), /not \{report/);
    assert.throws(() => parseSimulateResult({ report }), /not \{report/);
  });
});

describe("isCancelledRequest", () => {
  it("goes by the error code, not by words in the message", () => {
    assert.equal(isCancelledRequest({ code: -32800, message: "simulation cancelled" }), true);
    assert.equal(isCancelledRequest({ code: -32802, message: "" }), true);
    const failure = Object.assign(new Error("/w/cancel.rdcd:2:5: error[E003]: unexpected ':='"), { code: -32803 });
    assert.equal(isCancelledRequest(failure), false);
    assert.equal(isCancelledRequest(new Error("cancelled")), false);
    assert.equal(isCancelledRequest(undefined), false);
  });
});
