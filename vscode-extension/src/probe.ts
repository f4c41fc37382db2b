// The file-system and process side of finding the server (see serverCommand.ts for the logic).
import { execFile } from "node:child_process";
import * as fs from "node:fs";
import * as os from "node:os";
import { pathCandidates, SERVER_MODULE, type ServerProbe } from "./serverCommand";

export function isExecutable(path: string): boolean {
  try {
    if (!fs.statSync(path).isFile()) {
      return false;
    }
    fs.accessSync(path, process.platform === "win32" ? fs.constants.F_OK : fs.constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

export function findOnPath(name: string): string | undefined {
  return pathCandidates(name, process.env["PATH"] ?? "", process.platform).find((candidate) => isExecutable(candidate));
}

export function canRunServerModule(python: string): Promise<boolean> {
  const code = `import importlib.util, sys; sys.exit(0 if importlib.util.find_spec("${SERVER_MODULE}.__main__") else 1)`;
  return new Promise((resolve) => {
    execFile(python, ["-c", code], { timeout: 15000 }, (error) => resolve(error === null));
  });
}

export function makeProbe(selected: string | undefined, workspaceFolder: string | undefined): ServerProbe {
  return {
    selectedPython: selected,
    homeDir: os.homedir(),
    workspaceFolder,
    isExecutable,
    findOnPath,
    canRunServerModule,
  };
}
