// The RDCD debugger in VS Code: F5 on an .rdcd file (no launch.json needed) and the adapter,
// `rdcd dap`, started with the interpreter the language server uses.
import * as vscode from "vscode";
import { adapterCommand, completeConfiguration, DEBUG_TYPE } from "./debugConfig";
import { makeProbe } from "./probe";
import { selectedPython } from "./python";
import { findServerCommand, isServerCommand } from "./serverCommand";

function activeRdcdFile(): string | undefined {
  const document = vscode.window.activeTextEditor?.document;
  return document?.languageId === "rdcd" && document.uri.scheme === "file" ? document.uri.fsPath : undefined;
}

function simulateSettings(resource: vscode.Uri | undefined): Parameters<typeof completeConfiguration>[1] {
  const simulate = vscode.workspace.getConfiguration("rdcd.simulate", resource);
  return {
    config: simulate.get<string>("config", "car7"),
    obstacle: simulate.get<string>("obstacle", "wall:1"),
    duration: simulate.get<number>("duration", 20),
    seed: simulate.get<number>("seed", 0),
    world: simulate.get<string>("world", ""),
    packetLoss: simulate.get<number>("packetLoss", 0),
    vm: simulate.get<string>("vm", ""),
    target: vscode.workspace.getConfiguration("rdcd", resource).get<string>("target", "default"),
  };
}

class ConfigurationProvider implements vscode.DebugConfigurationProvider {
  provideDebugConfigurations(): vscode.DebugConfiguration[] {
    return [{ type: DEBUG_TYPE, request: "launch", name: "Debug RDCD program", program: "${file}", stopOnEntry: false }];
  }

  resolveDebugConfiguration(
    folder: vscode.WorkspaceFolder | undefined,
    given: vscode.DebugConfiguration,
  ): vscode.DebugConfiguration | undefined {
    const file = activeRdcdFile();
    const config = completeConfiguration(given, simulateSettings(folder?.uri), file);
    if (config === undefined) {
      void vscode.window.showInformationMessage("Open an .rdcd file to debug it, or name it in launch.json (program).");
      return undefined;
    }
    if (config["cwd"] === undefined && folder !== undefined) {
      config["cwd"] = folder.uri.fsPath;
    }
    return config as vscode.DebugConfiguration;
  }
}

class AdapterFactory implements vscode.DebugAdapterDescriptorFactory {
  constructor(private readonly log: (message: string) => void) {}

  async createDebugAdapterDescriptor(session: vscode.DebugSession): Promise<vscode.DebugAdapterDescriptor> {
    if (!vscode.workspace.isTrusted) {
      throw new Error("The RDCD debugger runs simulations: trust this workspace to use it.");
    }
    const config = vscode.workspace.getConfiguration("rdcd.server");
    const folder = session.workspaceFolder?.uri.fsPath ?? vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;
    const probe = makeProbe(await selectedPython(vscode.window.activeTextEditor?.document.uri), folder);
    const server = await findServerCommand(
      { path: config.get<string>("path", ""), pythonPath: config.get<string>("pythonPath", ""), args: [] },
      probe,
    );
    if (!isServerCommand(server)) {
      throw new Error(server.error);
    }
    const found = adapterCommand(server, probe);
    if ("error" in found) {
      throw new Error(found.error);
    }
    this.log(`Starting the debugger: ${found.command} ${found.args.join(" ")}`);
    return new vscode.DebugAdapterExecutable(found.command, found.args, folder === undefined ? {} : { cwd: folder });
  }
}

export function registerDebugger(log: (message: string) => void): vscode.Disposable[] {
  const provider = new ConfigurationProvider();
  return [
    vscode.debug.registerDebugConfigurationProvider(DEBUG_TYPE, provider),
    // also listed by "Debug: Select and Start Debugging" → RDCD Simulator
    vscode.debug.registerDebugConfigurationProvider(DEBUG_TYPE, provider, vscode.DebugConfigurationProviderTriggerKind.Dynamic),
    vscode.debug.registerDebugAdapterDescriptorFactory(DEBUG_TYPE, new AdapterFactory(log)),
  ];
}
