// preview.ts: "NOME: Open Preview to the Side". A webview beside the editor runs the
// preview app (preview/, bundled into media/preview/ when the extension is built) and this
// side relays its JSON-RPC requests (nome/preview, nome/setParameter, nome/saveScene) to the
// running language server, so the picture comes from the same checked text as the
// squiggles. It follows the active NOME editor, tells the app `nome/changed` 250 ms after
// the user stops typing (the server keeps the last good geometry's session; a text with
// errors answers ok: false and the app keeps its picture), saves files the app offers
// ("Save as STL", "Save scene") through a save dialog, and "Write slider values into the
// file" replaces the document's text with the saved scene as one undoable edit.
import * as vscode from "vscode";
import type { LanguageClient } from "vscode-languageclient/node";

const kTypingDebounceMs = 250;
const kRelayed = new Set(["nome/preview", "nome/setParameter", "nome/saveScene"]);

export function isNomeDocument(d: vscode.TextDocument): boolean {
  return d.languageId === "nome";
}

export class PreviewPanel {
  static current: PreviewPanel | undefined;
  private readonly panel: vscode.WebviewPanel;
  private readonly disposables: vscode.Disposable[] = [];
  private document: vscode.TextDocument | undefined;
  private typing: ReturnType<typeof setTimeout> | undefined;
  private ready = false;

  static show(context: vscode.ExtensionContext, client: () => LanguageClient | undefined): void {
    const editor = vscode.window.activeTextEditor;
    if (PreviewPanel.current) {
      PreviewPanel.current.panel.reveal(vscode.ViewColumn.Beside, true);
    } else {
      PreviewPanel.current = new PreviewPanel(context, client);
    }
    if (editor && isNomeDocument(editor.document)) PreviewPanel.current.follow(editor.document);
  }

  private constructor(private context: vscode.ExtensionContext, private client: () => LanguageClient | undefined) {
    const media = vscode.Uri.joinPath(context.extensionUri, "media", "preview");
    this.panel = vscode.window.createWebviewPanel(
      "nomePreview",
      "NOME Preview",
      { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
      { enableScripts: true, retainContextWhenHidden: true, localResourceRoots: [media] }
    );
    this.panel.webview.html = "<!doctype html><p>Loading the NOME preview…</p>";
    void this.render(media);
    this.panel.onDidDispose(() => this.dispose(), null, this.disposables);
    this.panel.webview.onDidReceiveMessage((m) => void this.receive(m), null, this.disposables);
    vscode.window.onDidChangeActiveTextEditor(
      (e) => {
        if (e && isNomeDocument(e.document)) this.follow(e.document);
      },
      null,
      this.disposables
    );
    vscode.workspace.onDidChangeTextDocument(
      (e) => {
        if (e.document !== this.document || e.contentChanges.length === 0) return;
        clearTimeout(this.typing);
        this.typing = setTimeout(() => this.notify("nome/changed", { uri: e.document.uri.toString() }), kTypingDebounceMs);
      },
      null,
      this.disposables
    );
  }

  private async render(media: vscode.Uri): Promise<void> {
    const webview = this.panel.webview;
    let body: string;
    try {
      body = new TextDecoder().decode(await vscode.workspace.fs.readFile(vscode.Uri.joinPath(media, "body.html")));
    } catch {
      webview.html = "<!doctype html><p>The preview app is missing from this build of the extension (media/preview).</p>";
      return;
    }
    const nonce = Array.from({ length: 32 }, () => Math.floor(Math.random() * 36).toString(36)).join("");
    const script = webview.asWebviewUri(vscode.Uri.joinPath(media, "app.js"));
    const style = webview.asWebviewUri(vscode.Uri.joinPath(media, "style.css"));
    webview.html = `<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; img-src ${webview.cspSource} blob: data:; style-src ${webview.cspSource}; script-src 'nonce-${nonce}';">
<meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="stylesheet" href="${style}"><title>NOME Preview</title></head>
<body>${body}<script nonce="${nonce}" src="${script}"></script></body></html>`;
  }

  follow(document: vscode.TextDocument): void {
    this.document = document;
    this.panel.title = `Preview ${document.uri.path.replace(/^.*\//, "")}`;
    if (this.ready) this.notify("nome/open", { uri: document.uri.toString(), title: document.uri.path.replace(/^.*\//, "") });
  }

  private notify(method: string, params: unknown): void {
    void this.panel.webview.postMessage({ type: "rpc", message: { jsonrpc: "2.0", method, params } });
  }

  private async receive(m: any): Promise<void> {
    if (m?.type === "ready") {
      this.ready = true;
      if (this.document) this.follow(this.document);
    } else if (m?.type === "rpc") {
      await this.relay(m.message);
    } else if (m?.type === "saveFile") {
      await this.saveFile(String(m.name), m.base64 ? Buffer.from(String(m.data), "base64") : Buffer.from(String(m.data), "utf8"));
    } else if (m?.type === "writeIntoFile") {
      await this.writeIntoFile(String(m.text));
    }
  }

  private async relay(message: any): Promise<void> {
    const reply = (body: object) => void this.panel.webview.postMessage({ type: "rpc", message: { jsonrpc: "2.0", id: message.id, ...body } });
    const client = this.client();
    if (!kRelayed.has(message?.method)) return reply({ error: { code: -32601, message: `not relayed: ${message?.method}` } });
    if (client === undefined) return reply({ error: { code: -32099, message: "the NOME language server is not running" } });
    try {
      reply({ result: await client.sendRequest(message.method, message.params) });
    } catch (e: any) {
      reply({ error: { code: e?.code ?? -32603, message: e?.message ?? String(e) } });
    }
  }

  private async saveFile(name: string, data: Uint8Array): Promise<void> {
    const base = this.document ? vscode.Uri.joinPath(this.document.uri, "..", name) : undefined;
    const target = await vscode.window.showSaveDialog({ defaultUri: base, saveLabel: "Save" });
    if (target) await vscode.workspace.fs.writeFile(target, data);
  }

  private async writeIntoFile(saved: string): Promise<void> {
    const doc = this.document;
    if (doc === undefined) return;
    if (doc.uri.path.endsWith(".anom")) {
      // The saved form of saved work holds its base scene too: it belongs in a new file.
      void vscode.window.showWarningMessage("NOME: saved work (.anom) cannot take the values in place; use \"Save scene with these values\".");
      return;
    }
    // The saved scene starts with a `# Saved by nomec …` line of its own: not for the
    // user's file (whose own text, comments included, follows it unchanged).
    const text = saved.replace(/^# Saved by nomec --emit nome[^\n]*\n/, "");
    const edit = new vscode.WorkspaceEdit();
    edit.replace(doc.uri, new vscode.Range(doc.positionAt(0), doc.positionAt(doc.getText().length)), text);
    await vscode.workspace.applyEdit(edit);
  }

  private dispose(): void {
    PreviewPanel.current = undefined;
    clearTimeout(this.typing);
    for (const d of this.disposables) d.dispose();
  }
}
