// The Simulate panel's replay follows the debugger: after each stop the adapter (`rdcd dap`,
// debug/session.py) sends a custom DAP event `rdcd/moment` with the world's time and the module
// the stop is on; when the panel shows a run of the same program file, the replay page is told to
// seek there and show that module (sim/replay/viewer/src/main.js listens for `rdcd/seek`). The
// simulation is deterministic, so a run with the same program and options has the same moments.
// No `vscode` import: unit-tested.
import * as path from "node:path";

export const MOMENT_EVENT = "rdcd/moment";
export const SEEK_MESSAGE = "rdcd/seek";

export interface Moment {
  /** The world's simulated time, seconds. */
  readonly t: number;
  /** The module the stop is on, or null (at the start, between modules). */
  readonly module: number | null;
}

/** A stop's moment with the run the debugger runs: the report's option fields and `source_sha256`. */
export interface StopMoment extends Moment {
  readonly run?: Readonly<Record<string, unknown>> | undefined;
}

export interface SeekMessage extends Moment {
  readonly type: typeof SEEK_MESSAGE;
}

/** The moment of a debug session's custom event, or undefined for another event or a malformed body. */
export function parseMoment(event: string, body: unknown): StopMoment | undefined {
  if (event !== MOMENT_EVENT || typeof body !== "object" || body === null || Array.isArray(body)) {
    return undefined;
  }
  const { t, module, run } = body as Record<string, unknown>;
  if (typeof t !== "number" || !Number.isFinite(t) || t < 0) {
    return undefined;
  }
  if (module !== null && (typeof module !== "number" || !Number.isInteger(module) || module < 0)) {
    return undefined;
  }
  const named = typeof run === "object" && run !== null && !Array.isArray(run) ? (run as Record<string, unknown>) : undefined;
  return { t, module, run: named };
}

function shown(value: unknown): string {
  return value === undefined ? "unset" : JSON.stringify(value);
}

/**
 * How the run the replay shows (its report, and the hash of the text it simulated: replayStore's
 * sourceHash) differs from the debugged run, one phrase each ("duration_s 20 in the replay, 8 in
 * the debugger", "the program text"); empty when they match or the adapter did not say.
 */
export function runDifferences(
  debugged: Readonly<Record<string, unknown>> | undefined,
  report: Readonly<Record<string, unknown>>,
  sourceHash: string | undefined,
): string[] {
  if (debugged === undefined) {
    return [];
  }
  const out: string[] = [];
  for (const [key, value] of Object.entries(debugged)) {
    if (key === "source_sha256") {
      if (typeof value === "string" && sourceHash !== undefined && !value.startsWith(sourceHash)) {
        out.push("the program text");
      }
    } else if (JSON.stringify(report[key]) !== JSON.stringify(value)) {
      out.push(`${key} ${shown(report[key])} in the replay, ${shown(value)} in the debugger`);
    }
  }
  return out;
}

/**
 * The debug session's program as an absolute path: `program` of its launch configuration, relative
 * to its `cwd` (as the adapter reads it), or undefined when the configuration names none.
 */
export function sessionProgram(configuration: Record<string, unknown>, fallbackCwd?: string): string | undefined {
  const { program, cwd } = configuration;
  if (typeof program !== "string" || program === "") {
    return undefined;
  }
  const base = typeof cwd === "string" && cwd !== "" ? cwd : fallbackCwd;
  return base === undefined ? path.resolve(program) : path.resolve(base, program);
}

/** Whether two absolute paths name the same file (letter case ignored where the file system ignores it). */
export function samePath(a: string, b: string, ignoreCase: boolean): boolean {
  const norm = (p: string) => (ignoreCase ? path.normalize(p).toLowerCase() : path.normalize(p));
  return norm(a) === norm(b);
}

/**
 * The message for the replay page when the debugger stopped at `moment` debugging `program`, or
 * undefined when the panel shows no run of that file (`shownProgram`: the file of the run shown).
 */
export function seekMessage(
  moment: Moment,
  program: string | undefined,
  shownProgram: string | undefined,
  ignoreCase: boolean,
): SeekMessage | undefined {
  if (program === undefined || shownProgram === undefined || !samePath(program, shownProgram, ignoreCase)) {
    return undefined;
  }
  return { type: SEEK_MESSAGE, t: moment.t, module: moment.module };
}
