// The debugger's side that needs no `vscode` import (unit-tested): the command that starts
// `rdcd dap`, found the way the language server is, and a launch configuration completed from the
// rdcd.simulate.* settings.
import type { ServerCommand, ServerNotFound, ServerProbe } from "./serverCommand";

export const DEBUG_TYPE = "rdcd";
export const CLI_MODULE = "rdcd_core";
export const CLI_EXECUTABLE = "rdcd";

export interface AdapterCommand {
  readonly command: string;
  readonly args: string[];
}

function dirname(path: string): string {
  const cut = Math.max(path.lastIndexOf("/"), path.lastIndexOf("\\"));
  return cut < 0 ? "" : path.slice(0, cut + 1);
}

/**
 * `rdcd dap` for the interpreter or installation the language server was found in: the same
 * Python with `-m rdcd_core dap`, or the `rdcd` executable beside `rdcd-lsp` (else on PATH).
 */
export function adapterCommand(
  server: ServerCommand,
  probe: Pick<ServerProbe, "isExecutable" | "findOnPath">,
  platform: string = process.platform,
): AdapterCommand | ServerNotFound {
  if (server.source === "rdcd.server.pythonPath" || server.source === "python extension") {
    return { command: server.command, args: ["-m", CLI_MODULE, "dap"] };
  }
  const suffix = platform === "win32" && /\.exe$/i.test(server.command) ? ".exe" : "";
  const beside = dirname(server.command) + CLI_EXECUTABLE + suffix;
  if (dirname(server.command) !== "" && probe.isExecutable(beside)) {
    return { command: beside, args: ["dap"] };
  }
  const onPath = probe.findOnPath(CLI_EXECUTABLE);
  if (onPath !== undefined) {
    return { command: onPath, args: ["dap"] };
  }
  return {
    error: `The RDCD debugger was not found: no ${CLI_EXECUTABLE} executable beside ${server.command} or on PATH.`,
    setting: "rdcd.server",
  };
}

/** The rdcd.simulate.* settings and rdcd.target, as the launch attributes they stand for. */
export interface SimulateSettings {
  readonly config: string;
  readonly obstacle: string;
  readonly duration: number;
  readonly seed: number;
  readonly world: string;
  readonly packetLoss: number;
  readonly vm: string;
  readonly target: string;
}

export type LaunchConfiguration = Record<string, unknown> & {
  type?: string;
  request?: string;
  name?: string;
  program?: string;
};

/**
 * A launch configuration with every simulate option it leaves out taken from the settings; an
 * empty one (F5 without launch.json) debugs `file`, the active .rdcd editor's file. Undefined when
 * there is nothing to debug.
 */
export function completeConfiguration(
  given: LaunchConfiguration,
  settings: SimulateSettings,
  file: string | undefined,
): LaunchConfiguration | undefined {
  const config: LaunchConfiguration = { ...given };
  if (config.type === undefined && config.request === undefined && config.name === undefined) {
    if (file === undefined) {
      return undefined;
    }
    Object.assign(config, { type: DEBUG_TYPE, request: "launch", name: "Debug RDCD program", program: file });
  }
  if (config.program === undefined || config.program === "") {
    if (file === undefined) {
      return undefined;
    }
    config.program = file;
  }
  const defaults: Record<string, unknown> = {
    config: settings.config,
    obstacle: settings.obstacle,
    duration: settings.duration,
    seed: settings.seed,
    packetLoss: settings.packetLoss,
    target: settings.target,
  };
  if (settings.world !== "") {
    defaults["world"] = settings.world;
  }
  if (settings.vm !== "") {
    defaults["vm"] = settings.vm;
  }
  for (const [key, value] of Object.entries(defaults)) {
    if (config[key] === undefined) {
      config[key] = value;
    }
  }
  return config;
}
