// The last run of each document, kept in the extension's storage so that "RDCD: Open Last Replay"
// can show it again after the language server removed its temporary files (it does when it exits
// or restarts). One folder per document: replay.html, plot.png (if any) and run.json (the document
// and the report). At most `limit` documents; the least recently simulated are removed first.
// Every file is written to a temporary name beside it and renamed. No `vscode` import: unit-tested.
import { createHash, randomBytes } from "node:crypto";
import * as fs from "node:fs/promises";
import * as path from "node:path";
import { isRecord, parseSimulateResult, type SimulationReport } from "./simulateArgs";

export interface RunFiles {
  readonly replayPath: string | null;
  readonly plotPath: string | null;
  readonly report: SimulationReport;
  /** sourceHash() of the simulated text: the replay's lines are the lines of that text. */
  readonly sourceHash: string;
}

export interface SavedRun extends RunFiles {
  /** The simulated document. */
  readonly uri: string;
}

/** A short digest of a program's text (to tell whether the document changed since its run). */
export function sourceHash(text: string): string {
  return createHash("sha256").update(text, "utf8").digest("hex").slice(0, 32);
}

const RUN = "run.json";
const REPLAY = "replay.html";
const PLOT = "plot.png";

/** The folder name of a document's last run: a hash of its uri (any uri makes a safe name). */
export function runFolderName(uri: string): string {
  return createHash("sha256").update(uri, "utf8").digest("hex").slice(0, 24);
}

async function writeAtomically(target: string, data: string | Uint8Array): Promise<void> {
  const temporary = path.join(path.dirname(target), `.${path.basename(target)}.${randomBytes(6).toString("hex")}.tmp`);
  try {
    await fs.writeFile(temporary, data);
    await fs.rename(temporary, target);
  } catch (error) {
    await fs.rm(temporary, { force: true });
    throw error;
  }
}

export class ReplayStore {
  constructor(
    private readonly root: string,
    private readonly limit = 20,
  ) {}

  folderOf(uri: string): string {
    return path.join(this.root, runFolderName(uri));
  }

  /** Copies the run's files into the document's folder, replacing its previous run. */
  async save(uri: string, files: RunFiles): Promise<SavedRun> {
    const folder = this.folderOf(uri);
    await fs.mkdir(folder, { recursive: true });
    const replayPath = files.replayPath === null ? null : path.join(folder, REPLAY);
    const plotPath = files.plotPath === null ? null : path.join(folder, PLOT);
    // run.json last: a run is complete when it names the files, which are then in place
    if (files.replayPath !== null && replayPath !== null) {
      await writeAtomically(replayPath, await fs.readFile(files.replayPath));
    }
    if (files.plotPath !== null && plotPath !== null) {
      await writeAtomically(plotPath, await fs.readFile(files.plotPath));
    }
    const run = {
      uri,
      sourceHash: files.sourceHash,
      report: files.report,
      plotPath: plotPath !== null ? PLOT : null,
      replayPath: replayPath !== null ? REPLAY : null,
    };
    await writeAtomically(path.join(folder, RUN), JSON.stringify(run));
    for (const [stale, kept] of [[REPLAY, replayPath], [PLOT, plotPath]] as const) {
      if (kept === null) {
        await fs.rm(path.join(folder, stale), { force: true });
      }
    }
    await this.prune(folder);
    return { uri, replayPath, plotPath, report: files.report, sourceHash: files.sourceHash };
  }

  /** The document's last run, or undefined when there is none (or it is unreadable). */
  async load(uri: string): Promise<SavedRun | undefined> {
    const folder = this.folderOf(uri);
    let run: unknown;
    try {
      run = JSON.parse(await fs.readFile(path.join(folder, RUN), "utf8"));
    } catch {
      return undefined;
    }
    if (!isRecord(run) || run["uri"] !== uri || typeof run["sourceHash"] !== "string") {
      return undefined;
    }
    const hash = run["sourceHash"];
    const file = (name: unknown, expected: string) => (name === expected ? path.join(folder, expected) : null);
    try {
      const parsed = parseSimulateResult({
        report: run["report"],
        plotPath: file(run["plotPath"], PLOT),
        replayPath: file(run["replayPath"], REPLAY),
      });
      for (const kept of [parsed.replayPath, parsed.plotPath]) {
        if (kept !== null) {
          await fs.access(kept);
        }
      }
      return { uri, ...parsed, sourceHash: hash };
    } catch {
      return undefined;
    }
  }

  /** Removes the least recently saved runs beyond the limit (never `keep`). */
  private async prune(keep: string): Promise<void> {
    let names: string[];
    try {
      names = await fs.readdir(this.root);
    } catch {
      return;
    }
    const runs: { folder: string; time: number }[] = [];
    for (const name of names) {
      const folder = path.join(this.root, name);
      if (!/^[0-9a-f]{24}$/.test(name) || folder === keep) {
        continue;
      }
      const stat = await fs.stat(path.join(folder, RUN)).catch(() => undefined);
      runs.push({ folder, time: stat?.mtimeMs ?? 0 });
    }
    runs.sort((a, b) => b.time - a.time);
    for (const run of runs.slice(Math.max(0, this.limit - 1))) {
      await fs.rm(run.folder, { recursive: true, force: true });
    }
  }
}
