// RDCD: Simulate Current File — runs the server's rdcd.simulate and shows the result view.
import * as path from "node:path";
import * as vscode from "vscode";
import { LANGUAGE_ID, type ServerManager } from "./client";
import { renderErrorHtml, renderReportHtml } from "./reportHtml";
import { buildSimulateArgs, isCancelledRequest, parseSimulateResult } from "./simulateArgs";

export class SimulationView implements vscode.Disposable {
  private panel: vscode.WebviewPanel | undefined;

  constructor(private readonly server: ServerManager) {}

  async simulateCurrentFile(resource?: vscode.Uri): Promise<void> {
    if (!vscode.workspace.isTrusted) {
      void vscode.window.showWarningMessage("RDCD: simulation is disabled in an untrusted workspace.");
      return;
    }
    const document = await this.targetDocument(resource);
    if (document === undefined) {
      void vscode.window.showWarningMessage("RDCD: open an .rdcd file to simulate it.");
      return;
    }
    if (document.isDirty) {
      await document.save();
    }
    const settings = vscode.workspace.getConfiguration("rdcd.simulate", document.uri);
    const args = buildSimulateArgs(document.uri.toString(), {
      config: settings.get("config"),
      obstacle: settings.get("obstacle"),
      duration: settings.get("duration"),
      seed: settings.get("seed"),
      world: settings.get("world"),
      packetLoss: settings.get("packetLoss"),
      vm: settings.get("vm"),
    });
    const fileName = path.basename(document.uri.fsPath || document.uri.path);
    let raw: unknown;
    try {
      raw = await vscode.window.withProgress(
        {
          location: vscode.ProgressLocation.Notification,
          title: `RDCD: simulating ${fileName} on ${args[1].config} for ${args[1].duration} s`,
          cancellable: true,
        },
        (_progress, token) => this.server.executeCommand("rdcd.simulate", args, token),
      );
    } catch (error) {
      if (error instanceof vscode.CancellationError || isCancelledRequest(error)) {
        void vscode.window.showInformationMessage("RDCD: simulation cancelled.");
        return;
      }
      // the server's message is the first error, "file:line:column: error[CODE]: …", in one line
      const message = error instanceof Error ? error.message : String(error);
      this.show(fileName, null).webview.html = renderErrorHtml(fileName, message, this.panel?.webview.cspSource ?? "");
      void vscode.window.showErrorMessage(`RDCD: simulation failed: ${message}`);
      return;
    }
    let result;
    try {
      result = parseSimulateResult(raw);
    } catch (error) {
      void vscode.window.showErrorMessage(`RDCD: ${error instanceof Error ? error.message : String(error)}`);
      return;
    }
    const panel = this.show(fileName, result.plotPath);
    const plotSrc =
      result.plotPath === null
        ? undefined
        : panel.webview.asWebviewUri(vscode.Uri.file(result.plotPath)).with({ query: `t=${Date.now()}` }).toString();
    panel.webview.html = renderReportHtml({
      report: result.report,
      plotSrc,
      cspSource: panel.webview.cspSource,
      fileName,
    });
  }

  private async targetDocument(resource?: vscode.Uri): Promise<vscode.TextDocument | undefined> {
    if (resource instanceof vscode.Uri) {
      const document = await vscode.workspace.openTextDocument(resource);
      return document.languageId === LANGUAGE_ID ? document : undefined;
    }
    const document = vscode.window.activeTextEditor?.document;
    return document?.languageId === LANGUAGE_ID ? document : undefined;
  }

  private show(fileName: string, plotPath: string | null): vscode.WebviewPanel {
    const roots = plotPath === null ? [] : [vscode.Uri.file(path.dirname(plotPath))];
    if (this.panel === undefined) {
      this.panel = vscode.window.createWebviewPanel(
        "rdcd.simulation",
        `Simulation: ${fileName}`,
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        { enableScripts: false, enableFindWidget: true, localResourceRoots: roots },
      );
      this.panel.onDidDispose(() => {
        this.panel = undefined;
      });
    } else {
      this.panel.title = `Simulation: ${fileName}`;
      this.panel.webview.options = { enableScripts: false, localResourceRoots: roots };
      this.panel.reveal(undefined, true);
    }
    return this.panel;
  }

  dispose(): void {
    this.panel?.dispose();
  }
}
