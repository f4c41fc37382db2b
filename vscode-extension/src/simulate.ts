// RDCD: Simulate Current File — runs the server's rdcd.simulate and shows the result view: the
// replay (clicking an event reveals its line in the editor) with the summary and the plot in a
// second tab. RDCD: Open Last Replay shows a document's last run again (kept in the extension's
// storage by ReplayStore). While an rdcd debug session is stopped, the replay shows the same moment
// (replayFollow.ts).
import { randomBytes } from "node:crypto";
import * as fs from "node:fs/promises";
import * as path from "node:path";
import * as vscode from "vscode";
import { LANGUAGE_ID, type ServerManager } from "./client";
import { DEBUG_TYPE } from "./debugConfig";
import { parseMoment, runDifferences, seekMessage, sessionProgram, type StopMoment } from "./replayFollow";
import { renderReplayHtml, ReplayPageError, revealedLine } from "./replayHtml";
import { ReplayStore, sourceHash, type SavedRun } from "./replayStore";
import { renderErrorHtml, renderReportHtml } from "./reportHtml";
import { buildSimulateArgs, isCancelledRequest, parseSimulateResult } from "./simulateArgs";

export class SimulationView implements vscode.Disposable {
  private panel: vscode.WebviewPanel | undefined;
  /** The run the panel shows (the replay's lines are the lines of its document as simulated). */
  private shown: SavedRun | undefined;
  private readonly store: ReplayStore;
  /** Where the last stop of an rdcd debug session was (for a replay shown while it is stopped). */
  private stop: { readonly session: vscode.DebugSession; readonly program: string; readonly moment: StopMoment } | undefined;
  /** The (session, run) pair last warned about being different runs: said once, not at every step. */
  private warned: string | undefined;

  constructor(
    private readonly server: ServerManager,
    storageRoot: string,
    private readonly log: (message: string) => void,
  ) {
    this.store = new ReplayStore(path.join(storageRoot, "replays"));
  }

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
    const simulated = document.getText(); // the server simulates the text the editor has
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
      this.shown = undefined;
      this.show(fileName, [], false).webview.html = renderErrorHtml(fileName, message, this.panel?.webview.cspSource ?? "");
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
    const files = { ...result, sourceHash: sourceHash(simulated) };
    let run: SavedRun;
    try {
      run = await this.store.save(document.uri.toString(), files);
    } catch (error) {
      // shown from the server's files all the same; only Open Last Replay will not find it
      this.log(`could not keep the run for Open Last Replay: ${error instanceof Error ? error.message : String(error)}`);
      run = { uri: document.uri.toString(), ...files };
    }
    await this.showRun(fileName, run);
  }

  /** RDCD: Open Last Replay: the last run of the current .rdcd file, as its simulation showed it. */
  async openLastReplay(resource?: vscode.Uri): Promise<void> {
    const document = await this.targetDocument(resource);
    if (document === undefined) {
      void vscode.window.showWarningMessage("RDCD: open an .rdcd file to see its last replay.");
      return;
    }
    const fileName = path.basename(document.uri.fsPath || document.uri.path);
    const run = await this.store.load(document.uri.toString());
    if (run === undefined || run.replayPath === null) {
      void vscode.window.showInformationMessage(
        `RDCD: ${fileName} has no replay yet; run "RDCD: Simulate Current File" to make one.`,
      );
      return;
    }
    await this.showRun(fileName, run);
  }

  private async showRun(fileName: string, run: SavedRun): Promise<void> {
    let page: string | undefined;
    if (run.replayPath !== null) {
      try {
        page = await fs.readFile(run.replayPath, "utf8");
      } catch (error) {
        void vscode.window.showWarningMessage(`RDCD: cannot read the replay: ${error instanceof Error ? error.message : String(error)}`);
      }
    }
    const roots = [run.plotPath, run.replayPath].filter((file): file is string => file !== null).map((file) => path.dirname(file));
    const panel = this.show(fileName, roots, page !== undefined);
    this.shown = run;
    const plotSrc =
      run.plotPath === null
        ? undefined
        : panel.webview.asWebviewUri(vscode.Uri.file(run.plotPath)).with({ query: `t=${Date.now()}` }).toString();
    const view = { report: run.report, plotSrc, cspSource: panel.webview.cspSource, fileName };
    if (page !== undefined) {
      try {
        panel.webview.html = renderReplayHtml({ ...view, page, nonce: randomBytes(18).toString("base64") });
        return;
      } catch (error) {
        if (!(error instanceof ReplayPageError)) {
          throw error;
        }
        void vscode.window.showWarningMessage(`RDCD: the replay is not shown: ${error.message}`);
        panel.webview.options = { enableScripts: false, localResourceRoots: panel.webview.options.localResourceRoots ?? [] };
      }
    }
    panel.webview.html = renderReportHtml(view);
  }

  /** A custom event of a debug session: after each stop of an rdcd session, the replay shows that moment. */
  followDebugger(event: vscode.DebugSessionCustomEvent): void {
    if (event.session.type !== DEBUG_TYPE) {
      return;
    }
    const moment = parseMoment(event.event, event.body);
    const folder = event.session.workspaceFolder?.uri.fsPath ?? vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;
    const program = sessionProgram(event.session.configuration, folder);
    if (moment === undefined || program === undefined) {
      return;
    }
    this.stop = { session: event.session, program, moment };
    this.postMoment();
  }

  /** The debug session ended: a replay opened later starts at its beginning again. */
  debugSessionEnded(session: vscode.DebugSession): void {
    if (this.stop?.session.id === session.id) {
      this.stop = undefined;
    }
  }

  /** Tells the replay shown (if it shows a run of the debugged file) to seek to the last stop. */
  private postMoment(): void {
    const stop = this.stop;
    const run = this.shown;
    if (stop === undefined || run === undefined || this.panel === undefined) {
      return;
    }
    const uri = vscode.Uri.parse(run.uri, true);
    const shownProgram = uri.scheme === "file" ? uri.fsPath : undefined;
    const message = seekMessage(stop.moment, stop.program, shownProgram, process.platform === "win32" || process.platform === "darwin");
    if (message === undefined) {
      return;
    }
    void this.panel.webview.postMessage(message);
    const differences = runDifferences(stop.moment.run, run.report, run.sourceHash);
    const pair = `${stop.session.id} ${run.replayPath ?? ""} ${run.sourceHash}`;
    if (differences.length > 0 && this.warned !== pair) {
      this.warned = pair;
      const text = `RDCD: the replay is of another run than the debugged one (${differences.join("; ")}): it shows the same time of that run`;
      this.log(text);
      vscode.window.setStatusBarMessage(`$(warning) ${text}`, 15000);
    }
  }

  /** A message from the replay: an event was clicked; its line is shown in the document's editor. */
  private async reveal(message: unknown): Promise<void> {
    const run = this.shown;
    if (run === undefined || revealedLine(message, Number.MAX_SAFE_INTEGER) === undefined) {
      return;
    }
    const uri = run.uri;
    const document = await vscode.workspace.openTextDocument(vscode.Uri.parse(uri, true));
    const line = revealedLine(message, document.lineCount);
    if (line === undefined) {
      return;
    }
    if (sourceHash(document.getText()) !== run.sourceHash) {
      vscode.window.setStatusBarMessage(
        `$(warning) RDCD: ${path.basename(document.uri.fsPath || document.uri.path)} changed since this run; line ${line + 1} may have moved`,
        8000,
      );
    }
    const start = new vscode.Position(line, document.lineAt(line).firstNonWhitespaceCharacterIndex);
    const visible = vscode.window.visibleTextEditors.find((editor) => editor.document.uri.toString() === uri);
    const column = visible?.viewColumn ?? (this.panel?.viewColumn === vscode.ViewColumn.One ? vscode.ViewColumn.Two : vscode.ViewColumn.One);
    const editor = await vscode.window.showTextDocument(document, {
      viewColumn: column,
      preserveFocus: false,
      selection: new vscode.Range(start, start),
    });
    editor.revealRange(new vscode.Range(start, start), vscode.TextEditorRevealType.InCenterIfOutsideViewport);
  }

  private async targetDocument(resource?: vscode.Uri): Promise<vscode.TextDocument | undefined> {
    if (resource instanceof vscode.Uri) {
      const document = await vscode.workspace.openTextDocument(resource);
      return document.languageId === LANGUAGE_ID ? document : undefined;
    }
    const document = vscode.window.activeTextEditor?.document;
    return document?.languageId === LANGUAGE_ID ? document : undefined;
  }

  private show(fileName: string, folders: readonly string[], scripts: boolean): vscode.WebviewPanel {
    const roots = folders.map((folder) => vscode.Uri.file(folder));
    if (this.panel === undefined) {
      const panel = vscode.window.createWebviewPanel(
        "rdcd.simulation",
        `Simulation: ${fileName}`,
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        // the replay keeps its time and camera while the panel is hidden
        { enableScripts: scripts, enableFindWidget: true, localResourceRoots: roots, retainContextWhenHidden: true },
      );
      panel.onDidDispose(() => {
        this.panel = undefined;
        this.shown = undefined;
      });
      panel.webview.onDidReceiveMessage((message: unknown) => {
        if (typeof message === "object" && message !== null && (message as { type?: unknown }).type === "ready") {
          this.postMoment(); // a replay opened while the debugger is stopped starts at that moment
          return;
        }
        this.reveal(message).catch((error: unknown) =>
          this.log(`could not reveal the line: ${error instanceof Error ? error.message : String(error)}`),
        );
      });
      this.panel = panel;
    } else {
      this.panel.title = `Simulation: ${fileName}`;
      this.panel.webview.options = { enableScripts: scripts, localResourceRoots: roots };
      this.panel.reveal(undefined, true);
    }
    return this.panel;
  }

  dispose(): void {
    this.panel?.dispose();
  }
}
