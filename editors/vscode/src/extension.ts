// extension.ts: the VS Code side of NOME support. It starts `nomec --lsp` (the language
// server in nomec's lsp/ folder) over stdio for every `nome` document and restarts it on
// demand or when its settings change. It knows nothing of the language: diagnostics,
// hover, definitions, references and formatting all come from the server, and so does the
// geometry of the live preview (preview.ts).
import * as vscode from "vscode";
import {
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
  TransportKind,
} from "vscode-languageclient/node";
import { PreviewPanel } from "./preview";

let client: LanguageClient | undefined;
let traceChannel: vscode.OutputChannel | undefined;

// Builds the command line from `nome.server.path` and `nome.server.extraArgs`.
export function serverCommand(config: vscode.WorkspaceConfiguration): {
  command: string;
  args: string[];
} {
  const configured = (config.get<string>("server.path") ?? "").trim();
  const extra = config.get<string[]>("server.extraArgs") ?? [];
  return { command: configured === "" ? "nomec" : configured, args: ["--lsp", ...extra] };
}

function createClient(): LanguageClient {
  const config = vscode.workspace.getConfiguration("nome");
  const { command, args } = serverCommand(config);
  const serverOptions: ServerOptions = {
    run: { command, args, transport: TransportKind.stdio },
    debug: { command, args, transport: TransportKind.stdio },
  };
  traceChannel ??= vscode.window.createOutputChannel("NOME Language Server Trace");
  const clientOptions: LanguageClientOptions = {
    documentSelector: [
      { scheme: "file", language: "nome" },
      { scheme: "untitled", language: "nome" },
    ],
    traceOutputChannel: traceChannel,
    // `nome.dialect`: "auto" lets the server detect each file's dialect from its content.
    initializationOptions: { dialect: config.get<string>("dialect") ?? "auto" },
  };
  // The client reads the `nome.trace.server` setting itself (the id below is its prefix).
  return new LanguageClient("nome", "NOME Language Server", serverOptions, clientOptions);
}

async function startClient(): Promise<void> {
  client = createClient();
  try {
    await client.start();
  } catch (err) {
    const { command } = serverCommand(vscode.workspace.getConfiguration("nome"));
    void vscode.window.showErrorMessage(
      `NOME: could not start the language server \`${command} --lsp\` (${String(err)}). ` +
        "Install nomec or set `nome.server.path` to its full path."
    );
  }
}

async function stopClient(): Promise<void> {
  const running = client;
  client = undefined;
  if (running !== undefined) {
    try {
      await running.stop();
    } catch {
      // A server that already died cannot be stopped; starting a new one is all that matters.
    }
  }
}

async function restartClient(): Promise<void> {
  await stopClient();
  await startClient();
}

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  context.subscriptions.push(
    vscode.commands.registerCommand("nome.restartServer", restartClient),
    vscode.commands.registerCommand("nome.openPreviewToSide", () => PreviewPanel.show(context, () => client)),
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (
        event.affectsConfiguration("nome.server.path") ||
        event.affectsConfiguration("nome.server.extraArgs") ||
        event.affectsConfiguration("nome.dialect")
      ) {
        void restartClient();
      }
    })
  );
  await startClient();
}

export async function deactivate(): Promise<void> {
  await stopClient();
  traceChannel?.dispose();
  traceChannel = undefined;
}
