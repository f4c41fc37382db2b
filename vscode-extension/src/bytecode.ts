// RDCD: Show Bytecode — a read-only virtual document with the server's listing of a file.
import * as vscode from "vscode";
import { LANGUAGE_ID, type ServerManager } from "./client";
import { listingText } from "./listing";

export const BYTECODE_SCHEME = "rdcd-bytecode";

export class BytecodeProvider implements vscode.TextDocumentContentProvider, vscode.Disposable {
  private readonly changed = new vscode.EventEmitter<vscode.Uri>();
  readonly onDidChange = this.changed.event;
  private readonly disposables: vscode.Disposable[] = [];
  private readonly timers = new Map<string, ReturnType<typeof setTimeout>>();

  constructor(private readonly server: ServerManager) {
    this.disposables.push(
      this.changed,
      vscode.workspace.onDidChangeTextDocument((event) => this.sourceChanged(event.document)),
      vscode.workspace.onDidSaveTextDocument((document) => this.sourceChanged(document)),
    );
  }

  static uriFor(source: vscode.Uri): vscode.Uri {
    return vscode.Uri.from({ scheme: BYTECODE_SCHEME, path: `${source.path}.bytecode`, query: source.toString() });
  }

  private sourceChanged(document: vscode.TextDocument): void {
    if (document.languageId !== LANGUAGE_ID) {
      return;
    }
    const uri = BytecodeProvider.uriFor(document.uri);
    if (!vscode.workspace.textDocuments.some((open) => open.uri.toString() === uri.toString())) {
      return;
    }
    const key = uri.toString();
    clearTimeout(this.timers.get(key));
    this.timers.set(
      key,
      setTimeout(() => {
        this.timers.delete(key);
        this.changed.fire(uri);
      }, 600),
    );
  }

  async provideTextDocumentContent(uri: vscode.Uri, token: vscode.CancellationToken): Promise<string> {
    const source = uri.query;
    try {
      const result = await this.server.executeCommand("rdcd.showBytecode", [source], token);
      return listingText(result);
    } catch (error) {
      return `; The bytecode of ${source} is not available:\n; ${error instanceof Error ? error.message : String(error)}\n`;
    }
  }

  async show(resource?: vscode.Uri): Promise<void> {
    const source =
      resource instanceof vscode.Uri
        ? resource
        : vscode.window.activeTextEditor?.document.languageId === LANGUAGE_ID
          ? vscode.window.activeTextEditor.document.uri
          : undefined;
    if (source === undefined) {
      void vscode.window.showWarningMessage("RDCD: open an .rdcd file to show its bytecode.");
      return;
    }
    const document = await vscode.workspace.openTextDocument(BytecodeProvider.uriFor(source));
    await vscode.window.showTextDocument(document, { viewColumn: vscode.ViewColumn.Beside, preview: true, preserveFocus: true });
  }

  dispose(): void {
    for (const timer of this.timers.values()) {
      clearTimeout(timer);
    }
    for (const disposable of this.disposables) {
      disposable.dispose();
    }
  }
}
