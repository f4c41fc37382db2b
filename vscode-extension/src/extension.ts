// The RDCD extension: starts the language server and adds the RDCD commands.
import * as vscode from "vscode";
import { BYTECODE_SCHEME, BytecodeProvider } from "./bytecode";
import { ServerManager } from "./client";
import { registerDebugger } from "./debug";
import { onDidChangePython } from "./python";
import { SimulationView } from "./simulate";

let manager: ServerManager | undefined;

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  const server = new ServerManager();
  manager = server;
  const storage = (context.storageUri ?? context.globalStorageUri).fsPath;
  const simulation = new SimulationView(server, storage, (message) => server.outputChannel.appendLine(message));
  const bytecode = new BytecodeProvider(server);
  context.subscriptions.push(
    server,
    simulation,
    bytecode,
    vscode.workspace.registerTextDocumentContentProvider(BYTECODE_SCHEME, bytecode),
    vscode.commands.registerCommand("rdcd.simulateCurrentFile", (resource?: vscode.Uri) =>
      simulation.simulateCurrentFile(resource),
    ),
    vscode.commands.registerCommand("rdcd.openLastReplay", (resource?: vscode.Uri) => simulation.openLastReplay(resource)),
    vscode.commands.registerCommand("rdcd.viewBytecode", (resource?: vscode.Uri) => bytecode.show(resource)),
    vscode.commands.registerCommand("rdcd.restartServer", () => server.restart()),
    vscode.commands.registerCommand("rdcd.showServerOutput", () => server.outputChannel.show()),
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (event.affectsConfiguration("rdcd.server")) {
        void server.restart();
      }
    }),
    vscode.workspace.onDidGrantWorkspaceTrust(() => void server.restart()),
    vscode.debug.onDidReceiveDebugSessionCustomEvent((event) => simulation.followDebugger(event)),
    vscode.debug.onDidTerminateDebugSession((session) => simulation.debugSessionEnded(session)),
    ...registerDebugger((message) => server.outputChannel.appendLine(message)),
  );
  const pythonChanged = await onDidChangePython(() => {
    const config = vscode.workspace.getConfiguration("rdcd.server");
    if (config.get<string>("path", "") === "" && config.get<string>("pythonPath", "") === "") {
      void server.restart();
    }
  });
  if (pythonChanged !== undefined) {
    context.subscriptions.push(pythonChanged);
  }
  void server.start();
}

export async function deactivate(): Promise<void> {
  await manager?.stop();
  manager = undefined;
}
