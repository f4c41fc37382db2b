// Finds the command that starts the RDCD language server. No `vscode` import: unit-tested.

export interface ServerSettings {
  /** rdcd.server.path: an rdcd-lsp executable (absolute, ~-relative, or a name on PATH). */
  readonly path: string;
  /** rdcd.server.pythonPath: an interpreter to run `-m server` with. */
  readonly pythonPath: string;
  /** rdcd.server.args: extra arguments for the server. */
  readonly args: readonly string[];
}

export interface ServerProbe {
  /** The interpreter selected in the Python extension, if any. */
  readonly selectedPython?: string | undefined;
  readonly homeDir: string;
  readonly workspaceFolder?: string | undefined;
  /** Whether an executable file exists at an absolute path. */
  isExecutable(path: string): boolean;
  /** The absolute path of an executable found on PATH, if any. */
  findOnPath(name: string): string | undefined;
  /** Whether `python -m server` can run (the interpreter has the rdcd package). */
  canRunServerModule(python: string): Promise<boolean>;
}

export type ServerSource = "rdcd.server.path" | "rdcd.server.pythonPath" | "python extension" | "PATH";

export interface ServerCommand {
  readonly command: string;
  readonly args: string[];
  readonly source: ServerSource;
}

export interface ServerNotFound {
  readonly error: string;
  /** The setting the user should look at. */
  readonly setting: string;
}

export const SERVER_EXECUTABLE = "rdcd-lsp";
export const SERVER_MODULE = "server";

/** Expands a leading `~` and `${workspaceFolder}` / `${userHome}` in a configured path. */
export function expandPath(raw: string, probe: Pick<ServerProbe, "homeDir" | "workspaceFolder">): string {
  let path = raw.trim();
  if (path === "~" || path.startsWith("~/")) {
    path = probe.homeDir + path.slice(1);
  }
  path = path.replace(/\$\{userHome\}/g, probe.homeDir);
  if (probe.workspaceFolder !== undefined) {
    path = path.replace(/\$\{workspaceFolder\}/g, probe.workspaceFolder);
  }
  return path;
}

function isBareName(path: string): boolean {
  return !path.includes("/") && !path.includes("\\");
}

function resolveExecutable(path: string, probe: ServerProbe): string | undefined {
  if (isBareName(path)) {
    return probe.findOnPath(path);
  }
  return probe.isExecutable(path) ? path : undefined;
}

/** The command a path setting names, or why it cannot be used (a wrong setting is not skipped). */
function fromSetting(
  setting: "rdcd.server.path" | "rdcd.server.pythonPath",
  raw: string,
  args: string[],
  probe: ServerProbe,
): ServerCommand | ServerNotFound {
  const found = resolveExecutable(expandPath(raw, probe), probe);
  if (found === undefined) {
    return {
      error: `The RDCD language server was not found: ${setting} is "${raw}", which is not an executable file.`,
      setting,
    };
  }
  return { command: found, args, source: setting };
}

/**
 * The order: the rdcd.server.path setting; the rdcd.server.pythonPath setting; the interpreter
 * selected in the Python extension (only when it has the rdcd package); rdcd-lsp on PATH.
 * A setting that is given but wrong is an error rather than a silent fallback.
 */
export async function findServerCommand(
  settings: ServerSettings,
  probe: ServerProbe,
): Promise<ServerCommand | ServerNotFound> {
  const extra = [...settings.args];
  if (settings.path.trim() !== "") {
    return fromSetting("rdcd.server.path", settings.path, extra, probe);
  }
  if (settings.pythonPath.trim() !== "") {
    return fromSetting("rdcd.server.pythonPath", settings.pythonPath, ["-m", SERVER_MODULE, ...extra], probe);
  }
  const selected = probe.selectedPython;
  if (selected !== undefined && selected !== "" && (await probe.canRunServerModule(selected))) {
    return { command: selected, args: ["-m", SERVER_MODULE, ...extra], source: "python extension" };
  }
  const onPath = probe.findOnPath(SERVER_EXECUTABLE);
  if (onPath !== undefined) {
    return { command: onPath, args: extra, source: "PATH" };
  }
  return {
    error:
      "The RDCD language server was not found: install the rdcd package (pip install -e . in the rdcd project) " +
      "so that rdcd-lsp is on PATH, or set rdcd.server.path or rdcd.server.pythonPath.",
    setting: "rdcd.server",
  };
}

export function isServerCommand(value: ServerCommand | ServerNotFound): value is ServerCommand {
  return "command" in value;
}

/** Candidate file names for `name` in the directories of a PATH string. */
export function pathCandidates(name: string, pathEnv: string, platform: string): string[] {
  const separator = platform === "win32" ? ";" : ":";
  const suffixes = platform === "win32" ? [".exe", ".cmd", ".bat", ""] : [""];
  const candidates: string[] = [];
  for (const dir of pathEnv.split(separator)) {
    if (dir === "") {
      continue;
    }
    const base = dir.endsWith("/") || dir.endsWith("\\") ? dir : dir + (platform === "win32" ? "\\" : "/");
    for (const suffix of suffixes) {
      candidates.push(base + name + suffix);
    }
  }
  return candidates;
}
