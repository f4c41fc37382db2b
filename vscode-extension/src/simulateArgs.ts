// Builds the arguments of the server's rdcd.simulate command from the settings, and reads its
// answer. No `vscode` import.

export interface SimulateSettings {
  readonly config?: unknown;
  readonly obstacle?: unknown;
  readonly duration?: unknown;
  readonly seed?: unknown;
  readonly world?: unknown;
  readonly packetLoss?: unknown;
  readonly vm?: unknown;
}

export interface SimulateOptions {
  config: string;
  /** none, wall:D or box:X,Y,W,L (metres). */
  obstacle: string;
  duration: number;
  seed: number;
  world?: string;
  /** Probability that an IR packet is lost, 0..1; sent only when above 0. */
  packetLoss?: number;
  /** VM profile of the modules: "default" or "original" (the ATRON firmware); sent only when set. */
  vm?: string;
}

export const SIMULATE_DEFAULTS: Readonly<SimulateOptions> = {
  config: "car7",
  obstacle: "wall:1",
  duration: 20,
  seed: 0,
};

function finite(value: unknown): number | undefined {
  return typeof value === "number" && Number.isFinite(value) ? value : undefined;
}

/** The obstacle as the simulator's SPEC: a number D means `wall:D`, null means `none`. */
export function obstacleSpec(value: unknown): string {
  if (value === null) {
    return "none";
  }
  const distance = finite(value);
  if (distance !== undefined) {
    return distance >= 0 ? `wall:${distance}` : SIMULATE_DEFAULTS.obstacle;
  }
  if (typeof value === "string" && value.trim() !== "") {
    return value.trim();
  }
  return SIMULATE_DEFAULTS.obstacle;
}

/** The options object of `rdcd.simulate`; wrong-typed settings fall back to the defaults. */
export function simulateOptions(settings: SimulateSettings): SimulateOptions {
  const config = typeof settings.config === "string" && settings.config.trim() !== "" ? settings.config.trim() : SIMULATE_DEFAULTS.config;
  const obstacle = obstacleSpec(settings.obstacle);
  const durationValue = finite(settings.duration);
  const duration = durationValue !== undefined && durationValue > 0 ? durationValue : SIMULATE_DEFAULTS.duration;
  const seedValue = finite(settings.seed);
  const seed = seedValue !== undefined ? Math.trunc(seedValue) : SIMULATE_DEFAULTS.seed;
  const options: SimulateOptions = { config, obstacle, duration, seed };
  if (typeof settings.world === "string" && settings.world.trim() !== "") {
    options.world = settings.world.trim();
  }
  const packetLoss = finite(settings.packetLoss);
  if (packetLoss !== undefined && packetLoss > 0 && packetLoss <= 1) {
    options.packetLoss = packetLoss;
  }
  if (typeof settings.vm === "string" && settings.vm.trim() !== "") {
    options.vm = settings.vm.trim();
  }
  return options;
}

/** `[uri, {config, obstacle, duration, seed, world?, packetLoss?, vm?}]`, the arguments of executeCommand rdcd.simulate. */
export function buildSimulateArgs(uri: string, settings: SimulateSettings): [string, SimulateOptions] {
  return [uri, simulateOptions(settings)];
}

/** JSON-RPC's RequestCancelled and LSP's ServerCancelled. */
const CANCELLED_CODES: readonly number[] = [-32800, -32802];

/**
 * Whether a failed rdcd.simulate request was cancelled (by the user or the server). Decided by the
 * error code: the message of a real failure names the user's file, and a file may be called cancel.rdcd.
 */
export function isCancelledRequest(error: unknown): boolean {
  return isRecord(error) && typeof error["code"] === "number" && CANCELLED_CODES.includes(error["code"]);
}

export function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** A module of the simulation report: its id, its final role, and what else the simulator records. */
export interface ReportModule {
  readonly id: number;
  readonly final_role: string | null;
  readonly [field: string]: unknown;
}

export interface ReportFragment {
  readonly name: string;
  readonly size: number;
}

/** The report of `rdcd simulate --report` (sim/report.py): modules, fragments and scalar figures. */
export interface SimulationReport {
  readonly modules: readonly ReportModule[];
  readonly fragments: readonly ReportFragment[];
  readonly [field: string]: unknown;
}

/** The server's answer to rdcd.simulate (server/commands.py). */
export interface SimulateResult {
  readonly report: SimulationReport;
  /** The trajectory plot, or null when the simulation drew none. */
  readonly plotPath: string | null;
}

function isModule(value: unknown): value is ReportModule {
  return isRecord(value) && typeof value["id"] === "number" && (value["final_role"] === null || typeof value["final_role"] === "string");
}

function isFragment(value: unknown): value is ReportFragment {
  return isRecord(value) && typeof value["name"] === "string" && typeof value["size"] === "number";
}

function isListOf<T>(value: unknown, isItem: (item: unknown) => item is T): value is T[] {
  return Array.isArray(value) && (value as unknown[]).every(isItem);
}

/** Reads the server's answer `{report, plotPath}`; throws when it is something else. */
export function parseSimulateResult(value: unknown): SimulateResult {
  if (!isRecord(value) || !isRecord(value["report"])) {
    throw new Error("The language server returned no simulation report.");
  }
  const { report, plotPath } = value;
  const { modules, fragments } = report;
  if (!isListOf(modules, isModule) || !isListOf(fragments, isFragment) || (plotPath !== null && typeof plotPath !== "string")) {
    throw new Error("The language server returned a simulation result that is not {report: {modules, fragments, …}, plotPath}.");
  }
  return { report: { ...report, modules, fragments }, plotPath };
}
