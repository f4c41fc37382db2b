import * as assert from "node:assert/strict";
import * as fs from "node:fs";
import * as os from "node:os";
import * as path from "node:path";
import { ReplayStore, runFolderName, sourceHash } from "../../src/replayStore";
import type { SimulationReport } from "../../src/simulateArgs";

const report: SimulationReport = { config: "car7", modules: [{ id: 0, final_role: "Axle" }], fragments: [{ name: "f", size: 3 }] };
const hash = sourceHash("role A { }\ndeployment { A }\n");

describe("ReplayStore", () => {
  let root: string;
  let server: string;

  beforeEach(() => {
    root = fs.mkdtempSync(path.join(os.tmpdir(), "rdcd-store-"));
    server = fs.mkdtempSync(path.join(os.tmpdir(), "rdcd-server-"));
  });

  afterEach(() => {
    fs.rmSync(root, { recursive: true, force: true });
    fs.rmSync(server, { recursive: true, force: true });
  });

  function serverFiles(tag: string): { replayPath: string; plotPath: string } {
    const replayPath = path.join(server, `replay-${tag}.html`);
    const plotPath = path.join(server, `plot-${tag}.png`);
    fs.writeFileSync(replayPath, `<!doctype html><title>${tag}</title>`);
    fs.writeFileSync(plotPath, Buffer.from([0x89, 0x50, 0x4e, 0x47, tag.length]));
    return { replayPath, plotPath };
  }

  it("keeps a copy of the run that outlives the server's files", async () => {
    const store = new ReplayStore(path.join(root, "replays"));
    const uri = "file:///work/a%20b/obstacle.rdcd";
    const files = serverFiles("one");
    const saved = await store.save(uri, { ...files, report, sourceHash: hash });
    fs.rmSync(server, { recursive: true, force: true }); // the server exits and removes its folder
    const loaded = await store.load(uri);
    assert.deepEqual(loaded, saved);
    assert.ok(loaded.replayPath?.startsWith(path.join(root, "replays", runFolderName(uri))));
    assert.equal(fs.readFileSync(loaded.replayPath ?? "", "utf8"), "<!doctype html><title>one</title>");
    assert.equal(fs.readFileSync(loaded.plotPath ?? "").length, 5);
    assert.deepEqual(loaded.report, report);
    assert.deepEqual(fs.readdirSync(store.folderOf(uri)).sort(), ["plot.png", "replay.html", "run.json"], "no temporary file left");
  });

  it("replaces the previous run of a document, also one without a plot", async () => {
    const store = new ReplayStore(root);
    const uri = "untitled:Untitled-1";
    await store.save(uri, { ...serverFiles("first"), report, sourceHash: hash });
    const second = await store.save(uri, { replayPath: serverFiles("second").replayPath, plotPath: null, report: { ...report, config: "car11" }, sourceHash: sourceHash("changed") });
    const loaded = await store.load(uri);
    assert.deepEqual(loaded, second);
    assert.equal(loaded.plotPath, null);
    assert.equal(loaded.report["config"], "car11");
    assert.equal(loaded.sourceHash, sourceHash("changed"));
    assert.equal(fs.readFileSync(loaded.replayPath ?? "", "utf8"), "<!doctype html><title>second</title>");
    assert.ok(!fs.existsSync(path.join(store.folderOf(uri), "plot.png")), "the older plot is gone");
  });

  it("knows no run of a document never simulated, and none whose files were damaged", async () => {
    const store = new ReplayStore(root);
    assert.equal(await store.load("file:///never.rdcd"), undefined);
    const uri = "file:///damaged.rdcd";
    await store.save(uri, { ...serverFiles("d"), report, sourceHash: hash });
    fs.rmSync(path.join(store.folderOf(uri), "replay.html"));
    assert.equal(await store.load(uri), undefined);
    await store.save(uri, { ...serverFiles("d"), report, sourceHash: hash });
    fs.writeFileSync(path.join(store.folderOf(uri), "run.json"), "{not json");
    assert.equal(await store.load(uri), undefined);
    fs.writeFileSync(path.join(store.folderOf(uri), "run.json"), JSON.stringify({ uri: "file:///other.rdcd", report, replayPath: "replay.html", plotPath: null }));
    assert.equal(await store.load(uri), undefined, "a folder of another document (a hash collision) is not taken");
    fs.writeFileSync(path.join(store.folderOf(uri), "run.json"), JSON.stringify({ uri, sourceHash: hash, report, replayPath: "../../etc/passwd", plotPath: null }));
    assert.equal((await store.load(uri))?.replayPath, null, "only its own file names count");
    fs.writeFileSync(path.join(store.folderOf(uri), "run.json"), JSON.stringify({ uri, report, replayPath: null, plotPath: null }));
    assert.equal(await store.load(uri), undefined, "a run without the hash of its text is not taken");
  });

  it("keeps the runs of at most `limit` documents, the newest", async () => {
    const store = new ReplayStore(root, 3);
    const uris = ["file:///1.rdcd", "file:///2.rdcd", "file:///3.rdcd", "file:///4.rdcd", "file:///5.rdcd"];
    for (const [index, uri] of uris.entries()) {
      await store.save(uri, { ...serverFiles(String(index)), report, sourceHash: hash });
      const time = new Date(Date.now() - (uris.length - index) * 10_000); // saved in this order
      fs.utimesSync(path.join(store.folderOf(uri), "run.json"), time, time);
    }
    const kept = [];
    for (const uri of uris) {
      if ((await store.load(uri)) !== undefined) {
        kept.push(uri);
      }
    }
    assert.deepEqual(kept, uris.slice(2));
    assert.equal(fs.readdirSync(root).length, 3);
  });

  it("tells texts apart by their hash", () => {
    assert.match(hash, /^[0-9a-f]{32}$/);
    assert.equal(sourceHash("role A { }\ndeployment { A }\n"), hash);
    assert.notEqual(sourceHash("role A { }\ndeployment { A }\n "), hash);
  });

  it("names folders by a hash of the uri, the same for the same uri", () => {
    assert.match(runFolderName("file:///a.rdcd"), /^[0-9a-f]{24}$/);
    assert.equal(runFolderName("file:///a.rdcd"), runFolderName("file:///a.rdcd"));
    assert.notEqual(runFolderName("file:///a.rdcd"), runFolderName("file:///A.rdcd"));
  });
});
