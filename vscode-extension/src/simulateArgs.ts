// Builds the arguments of the server's rdcd.simulate command from the settings. No `vscode` import.

export interface SimulateSettings {
  readonly config?: unknown;
  readonly obstacle?: unknown;
  readonly duration?: unknown;
  readonly seed?: unknown;
  readonly world?: unknown;
  readonly packetLoss?: unknown;
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
  return options;
}

/** `[uri, {config, obstacle, duration, seed, world?, packetLoss?}]`, the arguments of executeCommand rdcd.simulate. */
export function buildSimulateArgs(uri: string, settings: SimulateSettings): [string, SimulateOptions] {
  return [uri, simulateOptions(settings)];
}

export interface SimulateResult {
  readonly report: Record<string, unknown>;
  readonly plotPath: string | undefined;
}

/** Reads the server's answer: `{report, plotPath}`, where report may also come as JSON text. */
export function parseSimulateResult(value: unknown): SimulateResult {
  if (typeof value !== "object" || value === null) {
    throw new Error("The language server returned no simulation result.");
  }
  const record = value as Record<string, unknown>;
  let report: unknown = record["report"];
  if (typeof report === "string") {
    try {
      report = JSON.parse(report) as unknown;
    } catch {
      report = { text: report };
    }
  }
  if (typeof report !== "object" || report === null || Array.isArray(report)) {
    report = { result: report ?? null };
  }
  const plot = record["plotPath"] ?? record["plot_path"];
  return {
    report: report as Record<string, unknown>,
    plotPath: typeof plot === "string" && plot !== "" ? plot : undefined,
  };
}
