// Starts, stops and restarts the RDCD language server, and shows its state in the status bar.
import * as vscode from "vscode";
import {
  ExecuteCommandRequest,
  LanguageClient,
  type LanguageClientOptions,
  RevealOutputChannelOn,
  type ServerOptions,
  State,
} from "vscode-languageclient/node";
import { makeProbe } from "./probe";
import { selectedPython } from "./python";
import { findServerCommand, isServerCommand, type ServerCommand } from "./serverCommand";

export const LANGUAGE_ID = "rdcd";

function fragmentSizeHintsEnabled(): boolean {
  return vscode.workspace.getConfiguration("rdcd").get<boolean>("inlayHints.fragmentSizes", true);
}

/** What programs are checked and compiled for: "default" (this project's VM) or "original" (the firmware). */
function targetSetting(): string {
  return vscode.workspace.getConfiguration("rdcd").get<string>("target", "default");
}

function describe(command: ServerCommand): string {
  return `${[command.command, ...command.args].join(" ")} from ${command.source}`;
}

export class ServerManager implements vscode.Disposable {
  private client: LanguageClient | undefined;
  private readonly status: vscode.StatusBarItem;
  private readonly output: vscode.OutputChannel;
  private readonly disposables: vscode.Disposable[] = [];
  private starting: Promise<void> | undefined;

  constructor() {
    this.output = vscode.window.createOutputChannel("RDCD Language Server");
    this.status = vscode.window.createStatusBarItem("rdcd.server", vscode.StatusBarAlignment.Left, 0);
    this.status.name = "RDCD Language Server";
    this.status.command = "rdcd.showServerOutput";
    this.setStatus("stopped", "not started");
    this.disposables.push(
      this.status,
      this.output,
      vscode.window.onDidChangeActiveTextEditor(() => this.updateVisibility()),
    );
    this.updateVisibility();
  }

  get outputChannel(): vscode.OutputChannel {
    return this.output;
  }

  private updateVisibility(): void {
    const editor = vscode.window.activeTextEditor;
    if (editor !== undefined && editor.document.languageId === LANGUAGE_ID) {
      this.status.show();
    } else if (editor !== undefined) {
      this.status.hide();
    }
  }

  private setStatus(state: "starting" | "running" | "stopped" | "error", detail: string): void {
    const icons = { starting: "$(sync~spin)", running: "$(check)", stopped: "$(circle-slash)", error: "$(error)" };
    this.status.text = `${icons[state]} RDCD`;
    this.status.tooltip = `RDCD language server: ${state}${detail ? ` (${detail})` : ""}. Click to show its output.`;
    this.status.backgroundColor = state === "error" ? new vscode.ThemeColor("statusBarItem.errorBackground") : undefined;
    this.status.accessibilityInformation = { label: `RDCD language server ${state}${detail ? `: ${detail}` : ""}` };
  }

  /** Starts the server if it is not running; resolves when it is ready (or could not start). */
  start(): Promise<void> {
    if (this.client !== undefined && this.client.state === State.Running) {
      return Promise.resolve();
    }
    this.starting ??= this.doStart().finally(() => {
      this.starting = undefined;
    });
    return this.starting;
  }

  private async doStart(): Promise<void> {
    this.setStatus("starting", "");
    const config = vscode.workspace.getConfiguration("rdcd.server");
    const folder = vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;
    const found = await findServerCommand(
      {
        path: config.get<string>("path", ""),
        pythonPath: config.get<string>("pythonPath", ""),
        args: config.get<string[]>("args", []),
      },
      makeProbe(await selectedPython(vscode.window.activeTextEditor?.document.uri), folder),
    );
    if (!isServerCommand(found)) {
      this.setStatus("error", "not found");
      this.output.appendLine(found.error);
      void vscode.window.showErrorMessage(found.error, "Open Settings").then((choice) => {
        if (choice === "Open Settings") {
          void vscode.commands.executeCommand("workbench.action.openSettings", found.setting);
        }
      });
      return;
    }
    this.output.appendLine(`Starting ${found.command} ${found.args.join(" ")} (from ${found.source})`);
    const serverOptions: ServerOptions = {
      command: found.command,
      args: found.args,
      options: { ...(folder === undefined ? {} : { cwd: folder }), env: { ...process.env, PYTHONUNBUFFERED: "1" } },
    };
    const clientOptions: LanguageClientOptions = {
      documentSelector: [
        { scheme: "file", language: LANGUAGE_ID },
        { scheme: "untitled", language: LANGUAGE_ID },
      ],
      diagnosticCollectionName: "rdcd",
      outputChannel: this.output,
      revealOutputChannelOn: RevealOutputChannelOn.Never,
      // Pushes setting changes to servers that do not pull them with workspace/configuration.
      // eslint-disable-next-line @typescript-eslint/no-deprecated
      synchronize: { configurationSection: "rdcd" },
      // The server honours rdcd.inlayHints.fragmentSizes and rdcd.target: from here at start, then
      // through synchronize.
      initializationOptions: {
        inlayHints: { fragmentSizes: fragmentSizeHintsEnabled() },
        target: targetSetting(),
      },
    };
    const client = new LanguageClient("rdcd", "RDCD Language Server", serverOptions, clientOptions);
    this.client = client;
    client.onDidChangeState((event) => {
      if (this.client !== client) {
        return;
      }
      if (event.newState === State.Running) {
        this.setStatus("running", describe(found));
      } else if (event.newState === State.Starting) {
        this.setStatus("starting", "");
      } else {
        this.setStatus("stopped", "");
      }
    });
    try {
      await client.start();
      this.setStatus("running", describe(found));
    } catch (error) {
      this.setStatus("error", "failed to start");
      const message = `The RDCD language server (${found.command}) failed to start: ${String(error)}`;
      this.output.appendLine(message);
      void vscode.window.showErrorMessage(message, "Open Settings", "Show Output").then((choice) => {
        if (choice === "Open Settings") {
          void vscode.commands.executeCommand("workbench.action.openSettings", "rdcd.server");
        } else if (choice === "Show Output") {
          this.output.show();
        }
      });
    }
  }

  async stop(): Promise<void> {
    const client = this.client;
    this.client = undefined;
    if (client !== undefined) {
      try {
        await client.stop(5000);
      } catch (error) {
        this.output.appendLine(`Stopping the server: ${String(error)}`);
      }
    }
    this.setStatus("stopped", "");
  }

  async restart(): Promise<void> {
    await this.stop();
    await this.start();
  }

  /** Runs one of the server's workspace/executeCommand commands. */
  async executeCommand(command: string, args: unknown[], token?: vscode.CancellationToken): Promise<unknown> {
    await this.start();
    const client = this.client;
    if (client === undefined || client.state !== State.Running) {
      throw new Error("The RDCD language server is not running.");
    }
    return client.sendRequest(ExecuteCommandRequest.type, { command, arguments: args }, token);
  }

  dispose(): void {
    void this.stop();
    for (const disposable of this.disposables) {
      disposable.dispose();
    }
  }
}
